// xpbd against independent computations:
//   a radial spring oscillator, whose backward Euler energy has a closed form;
//   a crumpled flag, against the converged backward Euler step of Newton's solver;
//   chains=on on rows pulled straight along themselves, where one pass is that step;
//   the air's drag, implicit in velocity, against its closed form.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cloth/presets.h"
#include "cloth/solver.h"
#include "solver_spec.h"

using namespace cloth;

namespace {

// One free particle (1) between two pinned ones (0, 2) that both sit at the origin: two equal
// springs of rest length l0 pull it radially, a linear oscillator of omega^2 = 2 k / m in r - l0.
struct Oscillator {
    Model model;
    StepInput input;
};

Oscillator oscillator(Scalar k, Scalar h) {
    Points rest(3, 3);
    rest.col(0) = Vec3(0, 0, 0), rest.col(1) = Vec3(0.3, 0.4, 0), rest.col(2) = Vec3(0.6, 0, 0);  // |01| = |21| = 0.5
    Stiffness stiffness{k, k, k};
    Oscillator o{Model::fromMesh(rest, {{0, 1, 2}}, 0.3, stiffness), {}};
    o.input.h = h;
    o.input.pins = {{0, Vec3::Zero(), Vec3::Zero()}, {2, Vec3::Zero(), Vec3::Zero()}};
    return o;
}

}  // namespace

TEST(Xpbd, ARadialSpringLosesExactlyBackwardEulersEnergy) {
    // Backward Euler on m u'' = -2 k u maps the energy E to E / (1 + omega^2 h^2) each step.
    const Scalar k = 50, h = 1.0 / 240;
    Oscillator o = oscillator(k, h);
    const Scalar m = o.model.masses()[1], l0 = 0.5, omega2 = 2 * k / m;
    const Vec3 n(0.6, 0.8, 0);
    State s{Points::Zero(3, 3), Points::Zero(3, 3)};
    s.x.col(1) = (l0 + 0.05) * n;
    s.v.col(1) = 0.7 * n;
    auto energy = [&](const State& st) {
        const Scalar u = st.x.col(1).norm() - l0;
        return Scalar(0.5) * m * st.v.col(1).squaredNorm() + k * u * u;  // two springs
    };
    const Scalar e0 = energy(s);
    auto solver = solverOf("xpbd:iterations=200");
    Environment env;
    env.gravity.setZero();
    for (int step = 1; step <= 240; ++step) {
        ASSERT_EQ(solver->step(o.model, env, s, o.input).status, StepStatus::Ok);
        if (step % 60 == 0) {
            EXPECT_NEAR(energy(s) / e0, std::pow(1 + omega2 * h * h, -step), 1e-9) << "after " << step << " steps";
        }
    }
    EXPECT_LT(energy(s), 0.9 * e0) << "the test must see backward Euler's damping";
}

TEST(Xpbd, ManyPassesComeWithinAPercentOfNewtonsBackwardEulerStep) {
    // Gauss-Seidel's passes converge to where every constraint holds with its compliance; the sum
    // of their corrections differs from the backward Euler step only by how far the springs
    // turned within the step: at 960 Hz, 0.39% of the step's motion on this crumpled flag.
    HangingFlagDesc d;
    d.nx = d.ny = 6;
    HangingFlag flag = makeHangingFlag(d);
    std::mt19937 rng(5);
    std::uniform_real_distribution<Scalar> u(-1, 1);
    for (Index i = 0; i < flag.model.particleCount(); ++i) {
        flag.state.x.col(i) += 0.01 * Vec3(u(rng), u(rng), u(rng));
        flag.state.v.col(i) = 0.5 * Vec3(u(rng), u(rng), u(rng));
    }
    StepInput in;
    in.h = 1.0 / 960;
    in.pins = pinColumn(flag.model);
    for (Pin& p : in.pins) p.x = flag.state.x.col(p.particle);  // held where they are
    State be = flag.state, many = flag.state, once = flag.state;
    const StepResult newton =
        solverOf("newton:max_iterations=50,tolerance=1e-13,linear_tolerance=1e-12")->step(flag.model, {}, be, in);
    ASSERT_EQ(newton.status, StepStatus::Ok);
    ASSERT_LT(newton.residual, 1e-9) << "the reference step must be converged";
    ASSERT_EQ(solverOf("xpbd:iterations=1000")->step(flag.model, {}, many, in).status, StepStatus::Ok);
    ASSERT_EQ(solverOf("xpbd")->step(flag.model, {}, once, in).status, StepStatus::Ok);
    const Scalar moved = (be.x - flag.state.x).norm();
    EXPECT_LT((many.x - be.x).norm(), 0.01 * moved);
    EXPECT_GT((once.x - be.x).norm(), 0.1 * moved) << "one pass is not converged: the test can tell them apart";
}

TEST(Xpbd, OneChainPassIsTheBackwardEulerStepOfRowsPulledAlongThemselves) {
    // Shear and bend springs next to nothing, every free particle moving away from the pinned
    // column along its row: each row a straight chain stretched along itself, whose springs do not
    // turn, so one tridiagonal solve per row is the converged step. One Gauss-Seidel pass moves a
    // correction one spring along: far from it.
    HangingFlagDesc d;
    d.nx = 12, d.ny = 5;
    d.stiffness = {1e4, 1e-12, 1e-12};
    HangingFlag flag = makeHangingFlag(d);
    Environment env;
    env.gravity.setZero();
    for (Index i = 0; i < flag.model.particleCount(); ++i) flag.state.v.col(i) = Vec3(2, 0, 0);
    StepInput in;
    in.h = 1.0 / 240;
    in.pins = pinColumn(flag.model);
    State be = flag.state, chains = flag.state, gaussSeidel = flag.state;
    const StepResult newton =
        solverOf("newton:max_iterations=50,tolerance=1e-13,linear_tolerance=1e-12")->step(flag.model, env, be, in);
    ASSERT_LT(newton.residual, 1e-9) << "the reference step must be converged";
    ASSERT_EQ(solverOf("xpbd:chains=on")->step(flag.model, env, chains, in).status, StepStatus::Ok);
    ASSERT_EQ(solverOf("xpbd:chains=off")->step(flag.model, env, gaussSeidel, in).status, StepStatus::Ok);
    const Scalar moved = (be.x - flag.state.x).norm();
    EXPECT_LT((chains.x - be.x).norm(), 1e-5 * moved);
    EXPECT_GT((gaussSeidel.x - be.x).norm(), 0.1 * moved);
}

TEST(Xpbd, TheAirsDragIsImplicitInVelocity) {
    // A particle held by springs too soft to matter, in a drag f = C (w - v) with h C / m = 1000:
    // backward Euler gives v = (m v + h C w) / (m + h C); explicit Euler would overshoot w by 1000x.
    Oscillator o = oscillator(1e-9, 1.0 / 60);
    const Scalar m = o.model.masses()[1], c = 1000 * m / o.input.h;
    const Vec3 w(3, -1, 2), v0(0.5, 0.25, -1);
    State s{Points::Zero(3, 3), Points::Zero(3, 3)};
    s.x.col(1) = Vec3(0.3, 0.4, 0);
    s.v.col(1) = v0;
    Points force = Points::Zero(3, 3);
    force.col(1) = c * (w - v0);
    std::vector<Mat3> damping(3, Mat3::Zero());
    damping[1] = c * Mat3::Identity();
    o.input.externalForce = &force;
    o.input.damping = &damping;
    Environment env;
    env.gravity.setZero();
    ASSERT_EQ(solverOf("xpbd")->step(o.model, env, s, o.input).status, StepStatus::Ok);
    const Vec3 expected = (m * v0 + o.input.h * c * w) / (m + o.input.h * c);
    EXPECT_LT((s.v.col(1) - expected).norm(), 1e-9 * expected.norm());
}
