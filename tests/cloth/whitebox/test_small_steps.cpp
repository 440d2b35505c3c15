// small_steps (cloth/src/solvers/small_steps.cpp) against the double-precision integrator it
// makes fast, written out here: symplectic Euler in n substeps of h / n, the air recomputed at
// every substep (addAirForces), the pins moved on a straight line to their targets, a capsule
// met at every substep (resolveCollisions); its two-thread run against its one-thread run, bit
// for bit; its stability bound against the true highest frequency of a flag (a dense eigensolve);
// the demo flag's constraints after every substep against the same integrator with the
// constraints after each of its substeps, through a jump of the pole; its substeps paced by the
// pins against counts worked by hand; its stretch limit's cheap test against the squared lengths
// and tethers in double.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "cloth/air.h"
#include "cloth/collision.h"
#include "cloth/constraints.h"
#include "cloth/forces.h"
#include "cloth/presets.h"
#include "cloth/solver.h"
#include "physics_support.h"
#include "small_steps/stable_step.h"
#include "small_steps/constraint_check.h"
#include "small_steps/kernels.h"

using namespace cloth;
using namespace cloth::test;

namespace {

constexpr double kH = 1.0 / 240;

// The stiff flag (k = 1e4 / 1e4 / 1e3 N/m), n x n, in a 25 m/s wind, its pole swung sideways
// (and, with a jump, moved that far along z at once from the third step on).
struct Scenario {
    HangingFlag flag;
    AirParams air;
    Collider pole;
    std::vector<uint8_t> skip;
    double jump = 0;
    explicit Scenario(int n, HangingFlagDesc d = desc(0)) : flag(makeHangingFlag(withSide(d, n))) {
        air.wind = Vec3(25, 0, 5);
        pole.shape = Collider::Shape::Capsule;
        pole.axis = Vec3::UnitY();
        pole.halfExtents = Vec3(1.5, 0, 0);
        pole.radius = 0.03;
        skip.assign(std::size_t(flag.model.particleCount()), 0);
        for (const Pin& p : flag.pins) skip[std::size_t(p.particle)] = 1;
    }
    static HangingFlagDesc desc(int n) {
        HangingFlagDesc d;
        d.nx = d.ny = n;
        d.stiffness = {1e4, 1e4, 1e3};
        return d;
    }
    static HangingFlagDesc withSide(HangingFlagDesc d, int n) {
        d.nx = d.ny = n;
        return d;
    }
    // The pins of step s: the pole swung along z, the capsule with it.
    StepInput input(int s) {
        StepInput in;
        in.h = kH;
        in.pins = flag.pins;
        const double t = (s + 1) * kH, z = 0.2 * std::sin(8 * t) + (s >= 2 ? jump : 0), vz = 1.6 * std::cos(8 * t);
        for (Pin& p : in.pins) p.x.z() += z, p.v = Vec3(0, 0, vz);
        pole.center = Vec3(0, flag.pins.front().x.y() - 1.5, z);
        pole.velocity = Vec3(0, 0, vz);
        return in;
    }
};

// The double integrator written out: n substeps, each the air at that substep's state, one
// symplectic Euler substep with the pins on their straight line, then the capsule.
void referenceStep(Scenario& sc, const StepInput& in, int n, Solver& explicitEuler) {
    const std::vector<Pin> start = [&] {
        std::vector<Pin> pins = in.pins;
        for (Pin& p : pins) p.x = sc.flag.state.x.col(p.particle);
        return pins;
    }();
    std::vector<Collider> colliders{sc.pole};
    for (int s = 1; s <= n; ++s) {
        Points air = Points::Zero(3, sc.flag.model.particleCount());
        addAirForces(sc.flag.model, sc.flag.state, sc.air, air);
        StepInput sub;
        sub.h = in.h / n;
        sub.pins = in.pins;
        for (std::size_t k = 0; k < sub.pins.size(); ++k) sub.pins[k].x = start[k].x + (in.pins[k].x - start[k].x) * (double(s) / n);
        sub.externalForce = &air;
        ASSERT_EQ(explicitEuler.step(sc.flag.model, Environment{}, sc.flag.state, sub).status, StepStatus::Ok);
        resolveCollisions(colliders, 0.01, &sc.skip, sc.flag.state);
    }
}

// `steps` steps of small_steps on sc, with `within` as the solver's constraints; with `after`,
// these constraints once after each step.
State runSmallSteps(const std::string& spec, int steps, Scenario sc = Scenario(17), const Constraints& within = {},
                    ConstraintSet* after = nullptr) {
    auto solver = solverFor(spec);
    solver->setConstraints(within);
    std::vector<Collider> colliders;
    for (int s = 0; s < steps; ++s) {
        StepInput in = sc.input(s);
        colliders = {sc.pole};
        in.air = &sc.air, in.colliders = &colliders, in.thickness = 0.01, in.collisionSkip = &sc.skip;
        EXPECT_EQ(solver->step(sc.flag.model, Environment{}, sc.flag.state, in).status, StepStatus::Ok);
        if (after) after->apply(sc.flag.model, in.pins, in.h, sc.flag.state, nullptr);
    }
    return sc.flag.state;
}

// The demo flag (k = 1e3 / 1e2 / 5 N/m) with its tethers (2%) and stretch limit (10%, 4 passes),
// n x n, its pole jumping 0.3 m.
Constraints demoConstraints() {
    Constraints c;
    c.tether = 0.02, c.stretchLimit = 0.1, c.stretchPasses = 4;
    return c;
}
Scenario demoFlag(int n) {
    HangingFlagDesc d;
    d.stiffness = {1e3, 1e2, 5};
    Scenario sc(n, d);
    sc.jump = 0.3;
    return sc;
}

double rmsOverWidth(const Points& a, const Points& b) { return std::sqrt((a - b).colwise().squaredNorm().mean()) / 1.5; }

}  // namespace

// 12 steps of 40 substeps (0.05 s) of the swung flag in the wind, against the pole: float keeps
// the positions within 1e-5 of the flag's width (RMS; 15 um) of the double integrator's. (Over
// seconds the fluttering flag is chaotic and any two integrators part: the study judges that
// against the reference.) The same run with the air of each step's start held over its substeps
// is far farther: the check can tell.
TEST(SmallSteps, FollowsTheDoubleIntegratorWrittenOut) {
    constexpr int kSteps = 12;
    Scenario ref(17), held(17);
    auto explicitEuler = solverFor("explicit");
    for (int s = 0; s < kSteps; ++s) referenceStep(ref, ref.input(s), 40, *explicitEuler);
    const State fast = runSmallSteps("small_steps:substeps=40", kSteps);
    const double error = rmsOverWidth(fast.x, ref.flag.state.x);
    EXPECT_LT(error, 1e-5);
    auto heldSolver = solverFor("explicit:substeps=40");
    for (int s = 0; s < kSteps; ++s) {
        StepInput in = held.input(s);
        Points air = Points::Zero(3, held.flag.model.particleCount());
        addAirForces(held.flag.model, held.flag.state, held.air, air);
        in.externalForce = &air;
        ASSERT_EQ(heldSolver->step(held.flag.model, Environment{}, held.flag.state, in).status, StepStatus::Ok);
        resolveCollisions({held.pole}, 0.01, &held.skip, held.flag.state);
    }
    EXPECT_GT(rmsOverWidth(held.flag.state.x, ref.flag.state.x), 10 * error);
}

TEST(SmallSteps, TwoThreadsGiveTheBitsOfOne) {
    // The stiff flag without constraints, and the demo flag with its constraints (each thread
    // tests its own springs and particles against their bounds, thread 0 applies them), on
    // two threads although the cloth is small (parallel_from=0).
    const State one = runSmallSteps("small_steps:substeps=40,threads=1", 30);
    const State two = runSmallSteps("small_steps:substeps=40,threads=2,parallel_from=0", 30);
    EXPECT_TRUE(one.x == two.x && one.v == two.v);
    const State oneDemo = runSmallSteps("small_steps:substeps=40,threads=1", 30, demoFlag(17), demoConstraints());
    const State twoDemo = runSmallSteps("small_steps:substeps=40,threads=2,parallel_from=0", 30, demoFlag(17), demoConstraints());
    EXPECT_TRUE(oneDemo.x == twoDemo.x && oneDemo.v == twoDemo.v) << "with the demo flag's constraints";
}

// The springs' bound w_max on the stiff flag's rest state is at least its true highest angular
// frequency, the square root of the largest eigenvalue of M^-1/2 K M^-1/2 (K = -df/dx, every
// spring's Jacobian at rest, pins free), and not more than twice it.
TEST(SmallSteps, StabilityBoundHoldsTheTrueHighestFrequency) {
    const HangingFlag flag = makeHangingFlag(Scenario::desc(9));
    const int n = flag.model.particleCount();
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    for (const Spring& s : flag.model.springs()) {
        const Mat3 J = springJacobian(flag.state.x.col(s.i), flag.state.x.col(s.j), s.k, s.rest, true);
        K.block<3, 3>(3 * s.i, 3 * s.i) += J, K.block<3, 3>(3 * s.j, 3 * s.j) += J;
        K.block<3, 3>(3 * s.i, 3 * s.j) -= J, K.block<3, 3>(3 * s.j, 3 * s.i) -= J;
    }
    Eigen::VectorXd w(3 * n);
    for (int i = 0; i < n; ++i) w.segment<3>(3 * i).setConstant(1 / std::sqrt(flag.model.masses()[i]));
    const Eigen::MatrixXd A = w.asDiagonal() * K * w.asDiagonal();
    const double trueFrequency = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().maxCoeff());
    const double bound = springFrequencyBound(flag.model);
    EXPECT_GE(bound, trueFrequency);
    EXPECT_LE(bound, 2 * trueFrequency);
    // The substeps: h / (fraction 2 / w) rounded up.
    EXPECT_EQ(stableSubsteps(kH, bound, 0, 0.5), int(std::ceil(kH * bound / 1.0)));
}

// Through the 0.3 m jump the demo flag's tethers and stretch limit act at every substep (the jump
// takes 40 cm of the pins in one step). small_steps keeps the positions within 1e-4 of the width
// (RMS, float against double) of the double integrator written out with the constraints after
// each of its substeps, as the study's reference runs them; the constraints once per step, after
// the last substep, leave the flag far farther from it.
TEST(SmallSteps, RunsTheConstraintsAfterEverySubstep) {
    constexpr int kSteps = 12;
    Scenario ref = demoFlag(17);
    auto explicitEuler = solverFor("explicit");
    explicitEuler->setConstraints(demoConstraints());
    for (int s = 0; s < kSteps; ++s) referenceStep(ref, ref.input(s), 40, *explicitEuler);

    const auto spec = "small_steps:substeps=40";
    const State fast = runSmallSteps(spec, kSteps, demoFlag(17), demoConstraints());
    const double error = rmsOverWidth(fast.x, ref.flag.state.x);
    EXPECT_LT(error, 1e-4);

    ConstraintSet oncePerStep;
    oncePerStep.set(demoConstraints());
    const State once = runSmallSteps(spec, kSteps, demoFlag(17), {}, &oncePerStep);
    EXPECT_GT(rmsOverWidth(once.x, ref.flag.state.x), 10 * error);
}

// With max_move, the substeps split the largest move of a step into pieces of at most max_move: 1 m
// at 1 cm takes 100 substeps, not 101 by a rounding error; 1.005 m takes 101. The largest move is
// the farthest pin's, or a particle's at its speed relative to the pole's.
TEST(SmallSteps, PacesItsSubstepsByTheLargestMove) {
    EXPECT_EQ(pacedSubsteps(1.0, 0.01), 100);
    EXPECT_EQ(pacedSubsteps(1.005, 0.01), 101);
    EXPECT_EQ(pacedSubsteps(1.005, 0), 0);
    const std::vector<Vec3> start{Vec3(0, 0, 0), Vec3(1, 2, 3)}, end{Vec3(0.6, 0.8, 0), Vec3(1, 2, 3.5)};
    State s;
    s.x = Points::Zero(3, 2);
    s.v = Points::Zero(3, 2);
    s.v.colwise() = Vec3(20, 0, 0);  // both moving with the pole
    EXPECT_DOUBLE_EQ(largestMove(start, end, s, Vec3(20, 0, 0), 0.1), 1.0);
    s.v.col(1) = Vec3(20, 0, 30);  // 30 m/s across it: 3 m in 0.1 s
    EXPECT_DOUBLE_EQ(largestMove(start, end, s, Vec3(20, 0, 0), 0.1), 3.0);
}

// The solver takes the paced count where it exceeds the stability bound's: the 0.3 m jump of the
// demo flag's pole (on its 0.2 m swing) at 1 cm per substep, and the stability bound's count on
// the steps without a jump (the largest move worked out here from the state and the pins).
TEST(SmallSteps, ItsStepsTakeThePacedCountThroughAJump) {
    Scenario sc = demoFlag(17);
    auto solver = solverFor("small_steps:max_move=0.01");
    std::vector<Collider> colliders;
    for (int s = 0; s < 4; ++s) {
        StepInput in = sc.input(s);
        colliders = {sc.pole};
        in.air = &sc.air, in.colliders = &colliders, in.thickness = 0.01, in.collisionSkip = &sc.skip;
        double move = 0;
        for (const Pin& p : in.pins) move = std::max(move, (p.x - sc.flag.state.x.col(p.particle)).norm());
        for (Index i = 0; i < sc.flag.model.particleCount(); ++i)
            move = std::max(move, (sc.flag.state.v.col(i) - in.pins.front().v).norm() * kH);
        const int stable = stableSubsteps(kH, springFrequencyBound(sc.flag.model),
                                          airRateBound(sc.flag.model, sc.flag.state, &sc.air), 1);
        const StepResult r = solver->step(sc.flag.model, Environment{}, sc.flag.state, in);
        ASSERT_EQ(r.status, StepStatus::Ok);
        if (s == 2) {
            EXPECT_GT(int(std::ceil(move / 0.01)), stable);
        }
        EXPECT_EQ(r.iterations, std::max(stable, int(std::ceil(move / 0.01 - 1e-9)))) << "step " << s;
    }
}

// A 33 x 33 flag on the stencil with `constraints`, and float positions for ConstraintCheck.
struct CheckedFlag {
    HangingFlagDesc d = withSide33();
    HangingFlag flag = makeHangingFlag(d);
    StencilCloth cloth;
    ConstraintSet set;
    Vec3Field x;
    explicit CheckedFlag(const Constraints& constraints) {
        EXPECT_EQ(cloth.build(flag.model), "");
        set.set(constraints);
        x.assign(cloth.n, cloth.pad);
    }
    static HangingFlagDesc withSide33() {
        HangingFlagDesc d;
        d.nx = d.ny = 33;
        return d;
    }
};

TEST(SmallSteps, ItsConstraintCheckListsEverySpringOverItsLimitInDouble) {
    // Each row of a 33 x 33 flag laid along x at 1.1 (1 - 1e-5) of the rest spacing, with y steps
    // that bring each of its springs' squared length in double (from the float positions) to its
    // limit's times 1 + d, d random in +-3e-7: some float roundings (1e-7) apart, so that half the
    // row's springs are over by less than float resolves. Every spring over its limit in double
    // must be listed; none under 0.9998 of it may be (the other families fall where they fall).
    CheckedFlag f(Constraints{0, 0.1, 4});
    auto& [d, flag, cloth, set, x] = f;
    const StretchLimit& limit = set.stretchLimit(flag.model);
    ConstraintCheck check;
    const auto& springs = flag.model.passSprings();
    std::vector<Index> along(std::size_t(cloth.n), -1);  // the row spring from each particle to the next
    for (Index k = 0; k < Index(springs.size()); ++k)
        if (springs[std::size_t(k)].j == springs[std::size_t(k)].i + 1) along[std::size_t(springs[std::size_t(k)].i)] = k;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> off(-3e-7, 3e-7);
    const double spacing = d.width / (d.nx - 1), below = 1.1 * spacing * (1 - 1e-5);
    for (int r = 0; r < d.ny; ++r)
        for (int c = 0; c < d.nx; ++c) {
            const int p = r * d.nx + c;
            x.x.at()[p] = float(c * below), x.z.at()[p] = float(r * 1.1 * d.height / (d.ny - 1));
            if (c == 0) continue;
            const double dx = double(x.x.at()[p]) - x.x.at()[p - 1], target = limit.within(along[std::size_t(p - 1)]) * (1 + off(rng));
            x.y.at()[p] = float(x.y.at()[p - 1] + (c % 2 ? 1 : -1) * std::sqrt(target - dx * dx));
        }
    const SpringBits& listed = check.hints(cloth, flag.model, flag.pins, set, x).springs;
    int over = 0, overAlong = 0, listedCount = 0;
    for (Index k = 0; k < Index(springs.size()); ++k) {
        const int i = springs[std::size_t(k)].i, j = springs[std::size_t(k)].j;
        const double dx = double(x.x.at()[j]) - x.x.at()[i], dy = double(x.y.at()[j]) - x.y.at()[i],
                     dz = double(x.z.at()[j]) - x.z.at()[i];
        const double L2 = dx * dx + dy * dy + dz * dz;
        const bool isListed = (listed[std::size_t(k) / 64] >> (k % 64)) & 1;
        listedCount += isListed;
        if (L2 > limit.within(k)) {
            ++over, overAlong += j == i + 1;
            EXPECT_TRUE(isListed) << "spring " << k << " over its limit by " << L2 / limit.within(k) - 1;
        }
        if (L2 < 0.9998 * limit.within(k)) {
            EXPECT_FALSE(isListed) << "spring " << k;
        }
    }
    EXPECT_GT(overAlong, 33 * 32 / 4) << "the test should put many row springs over by a hair";
    EXPECT_GE(listedCount, over);
}

TEST(SmallSteps, ItsConstraintCheckListsEveryParticleBeyondItsTetherInDouble) {
    // Each particle of a 33 x 33 flag set, in its row's plane, at 1.02 (1 - 1e-5) of its rest
    // distance from its anchor along the row, then moved across the row (y) so that its squared
    // distance in double (from the float positions) is its bound's times 1 + d, d random in
    // +-3e-7. Every particle beyond its bound in double must be listed; none under 0.9998 of it.
    CheckedFlag f(Constraints{0.02, 0, 4});
    auto& [d, flag, cloth, set, x] = f;
    const Tethers& tethers = set.tethers(flag.model, flag.pins);
    ASSERT_EQ(tethers.tethered().size(), std::size_t(33 * 32));
    for (int r = 0; r < d.ny; ++r) x.z.at()[r * d.nx] = float(r * d.height / (d.ny - 1));  // the pins
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> off(-3e-7, 3e-7);
    std::vector<double> bound(std::size_t(cloth.n), 0);
    for (std::size_t k = 0; k < tethers.tethered().size(); ++k) {
        const int p = tethers.tethered()[k], a = tethers.anchors()[k];
        ASSERT_EQ(a, p / d.nx * d.nx) << "the anchor of " << p << " is its row's pin";
        const double limit = 1.02 * tethers.restDistances()[k];
        bound[std::size_t(p)] = limit * limit;
        x.x.at()[p] = float(limit * (1 - 1e-5)), x.z.at()[p] = x.z.at()[a];
        const double dx = double(x.x.at()[p]) - x.x.at()[a];
        x.y.at()[p] = float(std::sqrt(bound[std::size_t(p)] * (1 + off(rng)) - dx * dx));
    }
    ConstraintCheck check;
    const std::vector<Index>& listed = check.hints(cloth, flag.model, flag.pins, set, x).tethers;
    std::vector<std::uint8_t> isListed(std::size_t(cloth.n), 0);
    for (const Index k : listed) isListed[std::size_t(tethers.tethered()[std::size_t(k)])] = 1;
    EXPECT_TRUE(std::is_sorted(listed.begin(), listed.end()));
    int beyond = 0;
    for (std::size_t k = 0; k < tethers.tethered().size(); ++k) {
        const int p = tethers.tethered()[k], a = tethers.anchors()[k];
        const double dx = double(x.x.at()[p]) - x.x.at()[a], dy = double(x.y.at()[p]) - x.y.at()[a],
                     dz = double(x.z.at()[p]) - x.z.at()[a];
        const double L2 = dx * dx + dy * dy + dz * dz;
        if (L2 > bound[std::size_t(p)]) {
            ++beyond;
            EXPECT_TRUE(isListed[std::size_t(p)]) << "particle " << p << " beyond its bound by " << L2 / bound[std::size_t(p)] - 1;
        }
        if (L2 < 0.9998 * bound[std::size_t(p)]) {
            EXPECT_FALSE(isListed[std::size_t(p)]) << "particle " << p;
        }
    }
    EXPECT_GT(beyond, 33 * 32 / 4) << "the test should put many particles beyond by a hair";
}

// The fastest particle relative to the pole (the contact's move stride), kept per SIMD lane:
// against a plain loop in double over every range of a random set, a NaN among them skipped.
TEST(SmallSteps, TheFastestParticleIsThePlainLoopsOverEveryRange) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-20, 20);
    const int n = 75;
    std::vector<float> vx(n), vy(n), vz(n);
    for (int i = 0; i < n; ++i) vx[std::size_t(i)] = u(rng), vy[std::size_t(i)] = u(rng), vz[std::size_t(i)] = u(rng);
    vy[40] = std::nanf("");
    const float pole[3] = {1.5f, -0.25f, 3.0f};
    for (int begin = 0; begin < n; begin += 7)
        for (int end = begin; end <= n; end += 5) {
            double want = 0;
            for (int i = begin; i < end; ++i) {
                const float dx = vx[std::size_t(i)] - pole[0], dy = vy[std::size_t(i)] - pole[1], dz = vz[std::size_t(i)] - pole[2];
                const float d = dx * dx + dy * dy + dz * dz;
                if (d == d && d > want) want = d;
            }
            EXPECT_EQ(double(fastestSquaredKernel(vx.data(), vy.data(), vz.data(), pole, begin, end)), want)
                << "[" << begin << ", " << end << ")";
        }
}

