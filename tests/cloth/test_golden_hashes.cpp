// Determinism: FNV-1a hashes of a fixed 60-step run, per solver, equal for 1 and 2 threads,
// against tests/cloth/golden_hashes.txt. Solvers are configured only through spec strings.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "physics_support.h"
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <string>

#include "cloth/air.h"
#include "cloth/presets.h"

#ifndef FLAGSIM_TEST_DATA_DIR
#error "FLAGSIM_TEST_DATA_DIR must name the directory of golden_hashes.txt (tests/CMakeLists.txt)"
#endif

using namespace cloth;
using namespace cloth::test;

namespace {

// ---------------------------------------------------------------------------------------------
// Golden hashes

std::uint64_t stateHash(const State& s) {
    const std::uint64_t hx = fnv1a(s.x.data(), sizeof(Scalar) * s.x.size());
    return fnv1a(s.v.data(), sizeof(Scalar) * s.v.size(), hx);
}

std::string hex(std::uint64_t value) {
    std::ostringstream s;
    s << std::hex << std::setw(16) << std::setfill('0') << value;
    return s.str();
}

// The golden file: "<spec> <hex hash>" per line; '#' starts a comment line.
std::map<std::string, std::string> readGoldenHashes(const std::string& path) {
    std::map<std::string, std::string> golden;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string spec, hash;
        if (!(fields >> spec >> hash) || spec[0] == '#') continue;
        golden[spec] = hash;
    }
    return golden;
}

// The fixed scenario: a 17 x 17 hanging flag whose pole moves along a polynomial path (no libm
// calls, so nothing here depends on the C library's rounding), air on a side wind, light drag;
// 60 steps of 1/240 s. The air is an explicit force, except for newton, which couples it into its
// equations (input.air: its Jacobian in every linear solve).
State runGoldenScenario(const std::string& spec, const std::function<void(MultigridTuning&)>& tune) {
    HangingFlagDesc d;
    d.nx = d.ny = 17;
    HangingFlag flag = makeHangingFlag(d);
    const bool coupledAir = spec.rfind("newton", 0) == 0;
    auto solver = solverFor(spec, tune);
    if (!solver) return flag.state;
    Environment env;
    env.drag = 0.05;
    AirParams air;
    air.wind = Vec3(6, 0, 1.5);
    StepInput input;
    input.h = 1.0 / 240;
    Points external;
    for (int step = 1; step <= 60; ++step) {
        const Scalar t = step * input.h;
        const Vec3 offset(0.4 * t, 0.2 * t - 1.5 * t * t, 0.3 * t * t);
        const Vec3 velocity(0.4, 0.2 - 3 * t, 0.6 * t);
        const std::vector<Pin> pins = pinColumn(flag.model, offset, velocity);
        external.setZero(3, flag.model.particleCount());
        if (coupledAir) input.air = &air;
        else addAirForces(flag.model, flag.state, air, external);
        input.pins = pins;
        input.externalForce = &external;
        const StepResult r = solver->step(flag.model, env, flag.state, input);
        if (r.status != StepStatus::Ok) {
            ADD_FAILURE() << spec << ": step " << step << " failed: " << toString(r.status);
            break;
        }
    }
    return flag.state;
}

// Runs `base` with `threads` threads and compares the final state's hash with the golden value
// recorded for `base` (the same for every thread count).
// `base`: the spec, and the label of the hash; with a tuning, the label is the spec, a slash and
// a name for the tuning.
void expectGoldenHash(const std::string& base, int threads, const std::function<void(MultigridTuning&)>& tune = nullptr) {
    const std::string specOnly = base.substr(0, base.find('/'));
    const std::string spec = specOnly + (specOnly.find(':') == std::string::npos ? ":" : ",") +
                             "threads=" + std::to_string(threads);
    const std::string path = std::string(FLAGSIM_TEST_DATA_DIR) + "/golden_hashes.txt";
    const std::string computed = hex(stateHash(runGoldenScenario(spec, tune)));
    const auto golden = readGoldenHashes(path);
    const auto it = golden.find(base);
    ASSERT_TRUE(it != golden.end()) << "no golden hash for '" << base << "' in " << path
                                   << "; computed with " << spec << ": " << computed
                                   << " (add the line: " << base << " " << computed << ")";
    EXPECT_EQ(computed, it->second)
        << spec << ": final state hash " << computed << " differs from the golden " << it->second
        << " in " << path << ". If the change is intended, update that line to: " << base << " "
        << computed;
}

}  // namespace

// =============================================================================================
// 6. Determinism: golden hashes. One test per solver and thread count, so that ctest runs each
// in its own process; 1 and 2 threads must reproduce the same recorded hash.

TEST(GoldenHash, KangChoDoubleThreads1) { expectGoldenHash("kangcho", 1); }
TEST(GoldenHash, KangChoDoubleThreads2) { expectGoldenHash("kangcho", 2); }
TEST(GoldenHash, KangChoFloatThreads1) { expectGoldenHash("kangcho:precision=float", 1); }
TEST(GoldenHash, KangChoFloatThreads2) { expectGoldenHash("kangcho:precision=float", 2); }
TEST(GoldenHash, MultigridThreads1) { expectGoldenHash("multigrid", 1); }
TEST(GoldenHash, MultigridThreads2) { expectGoldenHash("multigrid", 2); }
TEST(GoldenHash, MultigridVCycleThreads1) {
    expectGoldenHash("multigrid:tolerance=0.001/v-cycles", 1, [](MultigridTuning& t) { t.kcycleLevels = 0; });
}
TEST(GoldenHash, MultigridColdStartThreads1) {
    expectGoldenHash("multigrid:tolerance=0.001/v-cycles-from-zero", 1, [](MultigridTuning& t) {
        t.kcycleLevels = 0;
        t.startHistory = 0;
    });
}
TEST(GoldenHash, MultigridMixedThreads1) { expectGoldenHash("multigrid:precision=mixed", 1); }
TEST(GoldenHash, MultigridMixedThreads2) { expectGoldenHash("multigrid:precision=mixed", 2); }
TEST(GoldenHash, NewtonBdf2Threads1) { expectGoldenHash("newton:integrator=bdf2", 1); }
TEST(GoldenHash, NewtonBdf2Threads2) { expectGoldenHash("newton:integrator=bdf2", 2); }
TEST(GoldenHash, NewtonCappedThreads1) { expectGoldenHash("newton:integrator=bdf2,max_iterations=2", 1); }
TEST(GoldenHash, NewtonCappedThreads2) { expectGoldenHash("newton:integrator=bdf2,max_iterations=2", 2); }
