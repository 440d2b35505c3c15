// Determinism of the front's every solver family as the front steps it: golden hashes of a fixed
// run of cloth::Cloth (the library's whole step: pins on a moving carrier, the air, the solve, the
// flag's tethers and stretch limit, the pole), one per configuration family of the study's front,
// equal for 1 and 2 threads where the kind has threads, against tests/cloth/golden_hashes.txt
// (lines "cloth/<name>"). The implicit-air configurations (multigrid, as the front runs it) carry
// the air's velocity blocks into their system, so a change of those blocks' bits fails here
// first; newton couples the whole air into its equations. The paper's step with contact on (the
// pole's capsule and self-contact, contact.h) covers the contact stage's bits, and the run must
// have its moves cut short by contact's bounds and self pairs found, or the hash would not cover
// them: its flag starts folded over itself.

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

#include "cloth/cloth.h"
#include "cloth/flag_on_pole.h"
#include "physics_support.h"

#ifndef FLAGSIM_TEST_DATA_DIR
#error "FLAGSIM_TEST_DATA_DIR must name the directory of golden_hashes.txt (tests/CMakeLists.txt)"
#endif

using namespace cloth;

namespace {

std::string hashOf(const State& s) {
    std::ostringstream out;
    out << std::hex << std::setw(16) << std::setfill('0')
        << test::fnv1a(s.v.data(), sizeof(Scalar) * s.v.size(), test::fnv1a(s.x.data(), sizeof(Scalar) * s.x.size()));
    return out.str();
}

std::string golden(const std::string& name) {
    std::ifstream in(std::string(FLAGSIM_TEST_DATA_DIR) + "/golden_hashes.txt");
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string label, hash;
        if (fields >> label >> hash && label == "cloth/" + name) return hash;
    }
    return {};
}

// A carrier with no libm call along its path: it accelerates, brakes and turns (the rotation's
// quaternion grows linearly and is normalized, so only sqrt and the basic operations enter).
RigidFrame carrierAt(double t) {
    RigidFrame c;
    c.position = Vec3(0.1 * t, 0, 6 * t * t - 8 * t * t * t);
    c.linearVelocity = Vec3(0.1, 0, 12 * t - 24 * t * t);
    c.rotation = Eigen::Quaterniond(1, 0, 0.4 * t, 0).normalized();
    c.angularVelocity = Vec3(0, 0.8, 0);
    return c;
}

struct Family {
    const char* name;  // the label in golden_hashes.txt, after "cloth/"
    const char* spec;
    bool constraints = true, implicitAir = false;
    int substeps = 1;
    bool contact = false;
};

// The flag's columns past the 11th folded back over it, 12 mm off its plane: layers that self
// contact keeps apart while the springs pull the fold open.
void foldOver(ClothDesc& desc, int nx) {
    const int fold = 10;
    for (Index i = 0; i < desc.start.cols(); ++i) {
        const Index row = i / nx, column = i % nx;
        if (column <= fold) continue;
        const Scalar crease = desc.start(2, row * nx + fold);
        desc.start(2, i) = 2 * crease - desc.start(2, i);
        desc.start(0, i) += 0.012;
    }
}

// The demo's flag at 17 x 12 on a 3 m pole with its air (6 m/s across), tethers at 2% and the
// stretch limit at 10%, meeting the pole and a floor its lower rows reach; 120 ticks of 1/240 s.
// `used` sums what contact found and did over the run.
State run(const SolverConfig& solver, const Family& family, ContactReport& used) {
    FlagDesc f;
    f.nx = 17, f.ny = 12;
    Pole pole;
    ClothSettings s;
    s.solver = solver;
    if (family.constraints) s.constraints.tether = 0.02, s.constraints.stretchLimit = 0.1;
    s.environment.drag = 0.05;
    s.air = s.collisions = true;
    s.airParams.wind = Vec3(6, 0, 1.5);
    s.implicitAir = family.implicitAir;
    s.substeps = family.substeps;
    s.contact.enabled = family.contact;
    ClothDesc desc = flagOnPole(f, pole, s.thickness);
    if (family.contact) foldOver(desc, f.nx);
    cloth::Cloth cloth(std::move(desc), s, carrierAt(0));
    Collider floor;
    floor.center = Vec3(0, 2.2, 0);
    for (int k = 1; k <= 120; ++k) {
        const RigidFrame c = carrierAt(k / 240.0);
        cloth.step(1.0 / 240, c, {poleCollider(pole, c), floor});
        used.selfPairs += cloth.contactReport().selfPairs, used.limited += cloth.contactReport().limited;
    }
    EXPECT_EQ(cloth.failures(), 0) << describe(solver);
    return cloth.state();
}

void expectGolden(const Family& f, int threads) {
    SolverConfig config;
    std::string error;
    std::string spec = f.spec;
    if (threads > 1) {
        spec += std::string(spec.find(':') == std::string::npos ? ":" : ",") + "threads=" + std::to_string(threads);
        if (spec.rfind("small_steps", 0) == 0) spec += ",parallel_from=0";  // the threads even on a small cloth
    }
    ASSERT_TRUE(parseSolverConfig(spec, config, &error)) << error;
    ContactReport used;
    const std::string computed = hashOf(run(config, f, used));
    if (f.contact) {
        EXPECT_TRUE(used.selfPairs > 0 && used.limited > 0) << used.selfPairs << " self pairs, " << used.limited << " moves cut";
    }
    const std::string want = golden(f.name);
    ASSERT_FALSE(want.empty()) << "no golden hash for cloth/" << f.name << "; computed " << computed
                               << " (add the line: cloth/" << f.name << " " << computed << ")";
    EXPECT_EQ(computed, want) << "cloth/" << f.name << " with " << spec << ": " << computed << " differs from the golden "
                              << want << ". If the change is intended, update the line and re-run the front's rows it moves.";
}

// The front's families (tools/study/cpp/configurations.cpp), each as the front runs it.
const Family kShipped{"kangcho", "kangcho"};
const Family kFloat{"kangcho_float", "kangcho:precision=float"};
const Family kNoConstraints{"kangcho_no_constraints", "kangcho", false};
const Family kChebyshev{"chebyshev_8", "chebyshev:iterations=8"};
const Family kDesbrun{"desbrun", "desbrun"};
const Family kMultigrid{"multigrid_implicit_air", "multigrid", true, true};
const Family kOneCycle{"multigrid_1_cycle_implicit_air", "multigrid:cycles=1", true, true};
const Family kNewton{"newton_bdf2_240_2", "newton:integrator=bdf2,max_iterations=2"};
const Family kXpbd{"xpbd_960", "xpbd", true, false, 4};
const Family kChains{"xpbd_chains_1920", "xpbd:chains=on", true, false, 8};
const Family kExplicit{"explicit_32", "explicit", true, false, 32};
const Family kTrueMotion{"small_steps_paced", "small_steps:max_move=0.01"};
const Family kReference{"reference", "explicit:substeps=1", true, false, 24};
const Family kContact{"kangcho_contact", "kangcho", true, false, 1, true};

}  // namespace

TEST(GoldenCloth, ShippedThreads1) { expectGolden(kShipped, 1); }
TEST(GoldenCloth, ShippedThreads2) { expectGolden(kShipped, 2); }
TEST(GoldenCloth, KangchoFloat) { expectGolden(kFloat, 1); }
TEST(GoldenCloth, KangchoNoConstraints) { expectGolden(kNoConstraints, 1); }
TEST(GoldenCloth, Chebyshev) { expectGolden(kChebyshev, 1); }
TEST(GoldenCloth, Desbrun) { expectGolden(kDesbrun, 1); }
TEST(GoldenCloth, MultigridImplicitAirThreads1) { expectGolden(kMultigrid, 1); }
TEST(GoldenCloth, MultigridImplicitAirThreads2) { expectGolden(kMultigrid, 2); }
TEST(GoldenCloth, MultigridOneCycleImplicitAir) { expectGolden(kOneCycle, 1); }
TEST(GoldenCloth, NewtonCappedThreads1) { expectGolden(kNewton, 1); }
TEST(GoldenCloth, NewtonCappedThreads2) { expectGolden(kNewton, 2); }
TEST(GoldenCloth, Xpbd) { expectGolden(kXpbd, 1); }
TEST(GoldenCloth, XpbdChains) { expectGolden(kChains, 1); }
TEST(GoldenCloth, Explicit) { expectGolden(kExplicit, 1); }
TEST(GoldenCloth, TrueMotionThreads1) { expectGolden(kTrueMotion, 1); }
TEST(GoldenCloth, TrueMotionThreads2) { expectGolden(kTrueMotion, 2); }
TEST(GoldenCloth, Reference) { expectGolden(kReference, 1); }
TEST(GoldenCloth, KangchoContact) { expectGolden(kContact, 1); }
