// xpbd against independent computations:
//   a radial spring oscillator, whose backward Euler energy has a closed form;
//   a crumpled flag, against the converged backward Euler step of Newton's solver;
//   chains=on on rows pulled straight along themselves, where one pass is that step;
//   the air's drag, implicit in velocity, against its closed form.

#include <gtest/gtest.h>

#include "cloth/presets.h"
#include "cloth/solver.h"
#include "solver_spec.h"
#include "spring_cases.h"

using namespace cloth;

TEST(Xpbd, ARadialSpringLosesExactlyBackwardEulersEnergy) { spring_cases::expectBackwardEulersEnergyLoss("xpbd:iterations=200"); }

TEST(Xpbd, ManyPassesComeWithinAPercentOfNewtonsBackwardEulerStep) {
    // Gauss-Seidel's passes converge to where every constraint holds with its compliance; the sum
    // of their corrections differs from the backward Euler step only by how far the springs
    // turned within the step: at 960 Hz, 0.39% of the step's motion on this crumpled flag.
    const spring_cases::AgainstNewton r = spring_cases::againstNewton("xpbd:iterations=1000", "xpbd", 1.0 / 960);
    EXPECT_LT(r.many, 0.01 * r.moved);
    EXPECT_GT(r.once, 0.1 * r.moved) << "one pass is not converged: the test can tell them apart";
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

TEST(Xpbd, TheAirsDragIsImplicitInVelocity) { spring_cases::expectImplicitDrag("xpbd"); }
