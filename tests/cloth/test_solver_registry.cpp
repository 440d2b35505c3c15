// A solver kind added in one file (tests/kinds/damped_explicit_kind.cpp) and registered: --help,
// the README's table, the parser, describe(), threads and the factory all see it, because they
// read the registry. Its own executable, so that the README's table test sees the library's kinds
// alone.

#include <gtest/gtest.h>

#include "cloth/solver_config.h"
#include "cloth/presets.h"
#include "tests/kinds/damped_explicit_kind.h"

using namespace cloth;

namespace {

class SolverRegistry : public ::testing::Test {
protected:
    void SetUp() override { registerDampedExplicit(); }
};

}  // namespace

TEST_F(SolverRegistry, ANewKindIsListedAfterTheLibrarysOwn) {
    const std::vector<std::string> names = solverKindNames();
    ASSERT_GE(names.size(), 2u);
    EXPECT_EQ(names.front(), "kangcho");
    EXPECT_EQ(names.back(), kDampedExplicit);
}

TEST_F(SolverRegistry, HelpAndTheReadmeTableListItsKeys) {
    const std::string help = solverHelp();
    EXPECT_NE(help.find("\n  damped_explicit  symplectic Euler with a velocity damping factor"), std::string::npos) << help;
    EXPECT_NE(help.find("    damping=[0, 1) (default 0.01)  velocity lost per step\n"), std::string::npos) << help;
    EXPECT_NE(help.find("    threads=[1, 64] (default 1)"), std::string::npos);
    const std::string table = solverTableMarkdown();
    EXPECT_NE(table.find("| **damped_explicit** | | | | symplectic Euler"), std::string::npos);
    EXPECT_NE(table.find("| | `damping` | `[0, 1)` | `0.01` | velocity lost per step |"), std::string::npos);
}

TEST_F(SolverRegistry, TheParserValidationAndThreadsReadItsKeys) {
    SolverConfig c;
    std::string error;
    ASSERT_TRUE(parseSolverConfig("damped_explicit:damping=0.5,threads=2", c, &error)) << error;
    EXPECT_EQ(describe(c), "damped_explicit:damping=0.5,threads=2");
    EXPECT_EQ(threadsOf(c), 2);
    EXPECT_FALSE(parseSolverConfig("damped_explicit:damping=1", c, &error));
    EXPECT_EQ(error, "solver 'damped_explicit' parameter damping has a bad value '1' (allowed: [0, 1))");
    EXPECT_FALSE(parseSolverConfig("damped_explicit:substeps=2", c, &error));
    EXPECT_NE(error.find("has no parameter 'substeps' (known: damping, threads)"), std::string::npos) << error;
    EXPECT_FALSE(registerSolverKind(dampedExplicitKind(), &error));
    EXPECT_EQ(error, "solver kind 'damped_explicit' exists already");
}

// One step from rest, where only gravity acts (every spring at its rest length, no air): each
// free particle's velocity is h g (1 - damping), its position x0 + h v; pins stay put.
TEST_F(SolverRegistry, ItsFactoryMakesTheSolverItDescribes) {
    HangingFlag flag = makeHangingFlag({});
    SolverConfig c;
    std::string error;
    ASSERT_TRUE(parseSolverConfig("damped_explicit:damping=0.25", c, &error)) << error;
    auto solver = makeSolver(c, &error);
    ASSERT_TRUE(solver) << error;
    const State before = flag.state;
    StepInput input;
    input.h = 0.01;
    input.pins = flag.pins;
    ASSERT_EQ(solver->step(flag.model, Environment{}, flag.state, input).status, StepStatus::Ok);
    const Vec3 v = input.h * Vec3(0, -9.81, 0) * 0.75;
    std::vector<bool> pinned(flag.model.particleCount(), false);
    for (const Pin& p : flag.pins) pinned[p.particle] = true;
    for (Index i = 0; i < flag.model.particleCount(); ++i) {
        if (pinned[i]) {
            EXPECT_EQ(flag.state.x.col(i), before.x.col(i)) << i;
            continue;
        }
        EXPECT_NEAR((flag.state.v.col(i) - v).norm(), 0, 1e-12) << i;
        EXPECT_NEAR((flag.state.x.col(i) - before.x.col(i) - input.h * v).norm(), 0, 1e-12) << i;
    }
}
