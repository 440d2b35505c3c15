#include "swung_pole.h"

#include <cmath>

#include "cloth/constraints.h"
#include "cloth/solver_config.h"

namespace bench {

namespace {
constexpr double kRadius = 0.15, kOmega = 2 * 3.14159265358979323846 * 2;  // m, rad/s
}  // namespace

cloth::HangingFlag flagOfSize(int n) {
    cloth::HangingFlagDesc d;
    d.nx = d.ny = n;
    return cloth::makeHangingFlag(d);
}

cloth::Vec3 poleOffset(int s) {
    const double t = s * kH;
    return {kRadius * std::sin(kOmega * t), 0, kRadius * (1 - std::cos(kOmega * t))};
}

cloth::Vec3 poleVelocity(int s) {
    const double t = s * kH;
    return {kRadius * kOmega * std::cos(kOmega * t), 0, kRadius * kOmega * std::sin(kOmega * t)};
}

cloth::StepInput inputOfStep(const cloth::HangingFlag& flag, Pole pole, int s) {
    cloth::StepInput in;
    in.h = kH;
    in.pins = flag.pins;
    if (pole == Pole::Still) return in;
    const cloth::Vec3 d = poleOffset(s), v = poleVelocity(s);
    for (cloth::Pin& p : in.pins) p.x += d, p.v = v;
    return in;
}

std::unique_ptr<cloth::Solver> demoSolver(const char* constraints) {
    cloth::SolverConfig demo;
    cloth::parseSolverConfig("kangcho:precision=float", demo, nullptr);
    auto solver = cloth::makeSolver(demo);
    cloth::Constraints c;
    cloth::parseConstraints(constraints, c, nullptr);
    solver->setConstraints(c);
    return solver;
}

void run(cloth::Solver& solver, cloth::HangingFlag& flag, Pole pole, int from, int to) {
    for (int s = from; s < to; ++s) solver.step(flag.model, cloth::Environment{}, flag.state, inputOfStep(flag, pole, s));
}

}  // namespace bench
