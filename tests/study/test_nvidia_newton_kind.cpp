// The study's nvidia_newton kind (tools/study/cpp/nvidia_newton_kind.cpp) against a stand-in for
// Newton's process (fake_newton_bridge.py, the same protocol and a step computed here by hand):
// the state, the pins, the air and the drag reach the process and its answer comes back to the
// right particles; a process that refuses, exits or cannot start stops the step with its reason.

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "nvidia_newton_kind.h"

namespace {

using cloth::Index;
using cloth::Vec3;

// The stand-in as the kind's Python, and FAKE_NEWTON_FAIL as the test asks; both undone after.
class StandIn {
public:
    explicit StandIn(const char* python = FLAGSIM_FAKE_NEWTON_BRIDGE, const char* fail = "") {
        setenv("FLAGSIM_NVIDIA_NEWTON_PYTHON", python, 1);
        setenv("FAKE_NEWTON_FAIL", fail, 1);
    }
    ~StandIn() { unsetenv("FLAGSIM_NVIDIA_NEWTON_PYTHON"), unsetenv("FAKE_NEWTON_FAIL"); }
};

cloth::GridDesc grid() {
    cloth::GridDesc g;
    g.nx = 4, g.ny = 3, g.width = 0.3, g.height = 0.2, g.totalMass = 0.06;
    return g;
}

struct PeerCase {
    cloth::Model model = cloth::Model::fromGrid(grid());
    cloth::Environment env;
    cloth::State state = cloth::State::atRest(model);
    cloth::Points air = cloth::Points::Zero(3, model.particleCount());
    cloth::StepInput input;
    PeerCase() {
        env.drag = 0.5;
        for (Index i = 0; i < model.particleCount(); ++i) {
            state.v.col(i) = Vec3(0.1 * double(i), -0.2, 0.05 * double(i % 3));
            air.col(i) = Vec3(0.01, 0.002 * double(i), -0.003);
        }
        input.h = 1.0 / 240;
        input.externalForce = &air;
        input.pins = {{0, Vec3(0.01, 0.02, 0.0), Vec3(2.4, 4.8, 0.0)}, {4, Vec3(0.0, 0.21, 0.01), Vec3(0.0, 2.4, 2.4)}};
    }
    std::unique_ptr<cloth::Solver> solver() {
        study::registerNvidiaNewton();
        cloth::SolverConfig c;
        std::string why;
        EXPECT_TRUE(cloth::parseSolverConfig("nvidia_newton:method=vbd", c, &why)) << why;
        return cloth::makeSolver(c);
    }
};

TEST(NvidiaNewtonKind, StepsThroughTheProcessWithTheLibrarysAirDragAndPins) {
    const StandIn standIn;
    PeerCase c;
    auto solver = c.solver();
    const cloth::State start = c.state;
    for (int step = 0; step < 3; ++step) {
        const cloth::State before = c.state;
        ASSERT_EQ(solver->step(c.model, c.env, c.state, c.input).status, cloth::StepStatus::Ok);
        for (Index i = 0; i < c.model.particleCount(); ++i) {
            if (i == 0 || i == 4) {  // on the pin's target with its velocity
                const cloth::Pin& p = c.input.pins[i == 0 ? 0 : 1];
                EXPECT_EQ(c.state.x.col(i), p.x);
                EXPECT_EQ(c.state.v.col(i), p.v);
                continue;
            }
            const double m = c.model.masses()[i], h = c.input.h;
            const Vec3 f = c.air.col(i) - c.env.drag * m * before.v.col(i);
            const Vec3 v = before.v.col(i) + h * (c.env.gravity + f / m);
            EXPECT_LT((c.state.v.col(i) - v).norm(), 1e-12) << "particle " << i << ", step " << step;
            EXPECT_LT((c.state.x.col(i) - (before.x.col(i) + h * v)).norm(), 1e-12) << "particle " << i;
        }
    }
    EXPECT_GT((c.state.x - start.x).norm(), 1e-4);  // it moved: the answers were not the state sent
    EXPECT_DOUBLE_EQ(solver->profile().solveMs, 1.5);  // the process's own time
}

void expectStepThrows(const char* python, const char* fail, const std::string& words) {
    const StandIn standIn(python, fail);
    PeerCase c;
    auto solver = c.solver();
    try {
        solver->step(c.model, c.env, c.state, c.input);
        FAIL() << "the step went on";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

TEST(NvidiaNewtonKind, AProcessThatRefusesOrExitsStopsTheStepWithItsReason) {
    expectStepThrows(FLAGSIM_FAKE_NEWTON_BRIDGE, "open", "nvidia_newton: ValueError: no such solver");
    expectStepThrows(FLAGSIM_FAKE_NEWTON_BRIDGE, "step", "nvidia_newton: RuntimeError: the stand-in refuses");
    expectStepThrows(FLAGSIM_FAKE_NEWTON_BRIDGE, "exit", "exited before it answered");
}

TEST(NvidiaNewtonKind, APythonThatIsNotThereIsNamed) {
    expectStepThrows("/nonexistent/python", "", "peer '/nonexistent/python': cannot start");
    expectStepThrows("/nonexistent/python", "", "tools/run study --nvidia-newton makes it");
}

}  // namespace
