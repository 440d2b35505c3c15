// vbd against independent computations:
//   a radial spring oscillator, whose backward Euler energy has a closed form;
//   a crumpled flag, against the converged backward Euler step of Newton's solver;
//   the air's drag, implicit in velocity, against its closed form;
//   the same bits on one thread and on two (a color's vertices are independent).

#include <gtest/gtest.h>

#include "cloth/presets.h"
#include "cloth/solver.h"
#include "solver_spec.h"
#include "spring_cases.h"

using namespace cloth;

TEST(Vbd, ARadialSpringLosesExactlyBackwardEulersEnergy) { spring_cases::expectBackwardEulersEnergyLoss("vbd:iterations=50"); }

TEST(Vbd, ManyPassesAreNewtonsBackwardEulerStep) {
    // Block descent on backward Euler's potential converges to its minimizer, which Newton's
    // solver finds to 1e-13: on a crumpled flag at 240 Hz, within 1e-8 of the step's motion.
    const spring_cases::AgainstNewton r = spring_cases::againstNewton("vbd:iterations=2000", "vbd:iterations=1", 1.0 / 240);
    EXPECT_LT(r.many, 1e-8 * r.moved);
    EXPECT_GT(r.once, 1e-3 * r.moved) << "one pass is not converged: the test can tell them apart";
}

TEST(Vbd, TheAirsDragIsImplicitInVelocity) { spring_cases::expectImplicitDrag("vbd"); }

TEST(Vbd, TheSameBitsOnOneThreadAndOnTwo) {
    HangingFlag flag = spring_cases::crumpledFlag(7);
    const StepInput in = spring_cases::heldPins(flag, 1.0 / 60);
    State one = flag.state, two = flag.state;
    for (int k = 0; k < 10; ++k) {
        ASSERT_EQ(solverOf("vbd:iterations=4,substeps=2")->step(flag.model, {}, one, in).status, StepStatus::Ok);
        ASSERT_EQ(solverOf("vbd:iterations=4,substeps=2,threads=2")->step(flag.model, {}, two, in).status, StepStatus::Ok);
    }
    EXPECT_TRUE(one.x == two.x && one.v == two.v);
    EXPECT_GT((one.x - flag.state.x).norm(), 0.01) << "the flag must move";
}
