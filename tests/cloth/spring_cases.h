#pragma once
// Cases that the position-based steps' tests (xpbd, vbd) share: a radial spring oscillator, whose
// backward Euler energy loss has a closed form; a particle in a stiff drag, whose backward Euler
// velocity has one; a crumpled flag for a converged step to be judged on.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "cloth/presets.h"
#include "cloth/solver.h"
#include "solver_spec.h"

namespace spring_cases {

using namespace cloth;

// One free particle (1) between two pinned ones (0, 2) that both sit at the origin: two equal
// springs of rest length l0 pull it radially, a linear oscillator of omega^2 = 2 k / m in r - l0.
struct Oscillator {
    Model model;
    StepInput input;
};

inline Oscillator oscillator(Scalar k, Scalar h) {
    Points rest(3, 3);
    rest.col(0) = Vec3(0, 0, 0), rest.col(1) = Vec3(0.3, 0.4, 0), rest.col(2) = Vec3(0.6, 0, 0);  // |01| = |21| = 0.5
    Stiffness stiffness{k, k, k};
    Oscillator o{Model::fromMesh(rest, {{0, 1, 2}}, 0.3, stiffness), {}};
    o.input.h = h;
    o.input.pins = {{0, Vec3::Zero(), Vec3::Zero()}, {2, Vec3::Zero(), Vec3::Zero()}};
    return o;
}

// Backward Euler on m u'' = -2 k u maps the energy E to E / (1 + omega^2 h^2) each step: 240 steps
// of `spec` checked against it every 60, to 1e-9.
inline void expectBackwardEulersEnergyLoss(const std::string& spec) {
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
    auto solver = solverOf(spec);
    Environment env;
    env.gravity.setZero();
    for (int step = 1; step <= 240; ++step) {
        ASSERT_EQ(solver->step(o.model, env, s, o.input).status, StepStatus::Ok);
        if (step % 60 == 0) {
            EXPECT_NEAR(energy(s) / e0, std::pow(1 + omega2 * h * h, -step), 1e-9) << spec << " after " << step << " steps";
        }
    }
    EXPECT_LT(energy(s), 0.9 * e0) << "the test must see backward Euler's damping";
}

// A particle held by springs too soft to matter, in a drag f = C (w - v) with h C / m = 1000:
// backward Euler gives v = (m v + h C w) / (m + h C); explicit Euler would overshoot w by 1000x.
inline void expectImplicitDrag(const std::string& spec) {
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
    ASSERT_EQ(solverOf(spec)->step(o.model, env, s, o.input).status, StepStatus::Ok);
    const Vec3 expected = (m * v0 + o.input.h * c * w) / (m + o.input.h * c);
    EXPECT_LT((s.v.col(1) - expected).norm(), 1e-9 * expected.norm()) << spec;
}

// A 6 x 6 flag pinned along its first column, shaken out of its rest shape.
inline HangingFlag crumpledFlag(int seed) {
    HangingFlagDesc d;
    d.nx = d.ny = 6;
    HangingFlag flag = makeHangingFlag(d);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Scalar> u(-1, 1);
    for (Index i = 0; i < flag.model.particleCount(); ++i) {
        flag.state.x.col(i) += 0.01 * Vec3(u(rng), u(rng), u(rng));
        flag.state.v.col(i) = 0.5 * Vec3(u(rng), u(rng), u(rng));
    }
    return flag;
}

// Its pins held where they are, for one step of h.
inline StepInput heldPins(const HangingFlag& flag, Scalar h) {
    StepInput in;
    in.h = h;
    in.pins = pinColumn(flag.model);
    for (Pin& p : in.pins) p.x = flag.state.x.col(p.particle);  // held where they are
    return in;
}

// One step of h on crumpledFlag(5), its pins held: by Newton's backward Euler step converged to
// 1e-13 and by the solvers `many` and `once`; how far each of those two lands from Newton's, and
// how far Newton's moved the flag.
struct AgainstNewton {
    Scalar many = 0, once = 0, moved = 0;
};

inline AgainstNewton againstNewton(const std::string& many, const std::string& once, Scalar h) {
    HangingFlag flag = crumpledFlag(5);
    const StepInput in = heldPins(flag, h);
    State be = flag.state, a = flag.state, b = flag.state;
    const StepResult newton =
        solverOf("newton:max_iterations=50,tolerance=1e-13,linear_tolerance=1e-12")->step(flag.model, {}, be, in);
    EXPECT_EQ(newton.status, StepStatus::Ok);
    EXPECT_LT(newton.residual, 1e-9) << "the reference step must be converged";
    EXPECT_EQ(solverOf(many)->step(flag.model, {}, a, in).status, StepStatus::Ok);
    EXPECT_EQ(solverOf(once)->step(flag.model, {}, b, in).status, StepStatus::Ok);
    return {(a.x - be.x).norm(), (b.x - be.x).norm(), (be.x - flag.state.x).norm()};
}

}  // namespace spring_cases
