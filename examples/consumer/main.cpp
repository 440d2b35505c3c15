// A 17x17 flag pinned along its left edge, stepped for two seconds by multigrid.
#include <cloth/diagnostics.h>
#include <cloth/presets.h>
#include <cloth/solver.h>
#include <cstdio>

int main() {
    cloth::HangingFlagDesc desc;
    desc.nx = desc.ny = 17;
    cloth::HangingFlag flag = cloth::makeHangingFlag(desc);  // model, state and the pins
    cloth::SolverConfig config;
    std::string error;
    if (!cloth::parseSolverConfig("multigrid", config, &error)) return std::puts(error.c_str()), 1;
    auto solver = cloth::makeSolver(config);
    cloth::StepInput input;
    input.h = 1.0 / 240;
    input.pins = flag.pins;
    for (int step = 0; step < 480; ++step)
        if (solver->step(flag.model, cloth::Environment{}, flag.state, input).status != cloth::StepStatus::Ok)
            return std::puts("step failed"), 1;
    const cloth::Diagnostics d = cloth::measure(flag.model, cloth::Environment{}, flag.state);
    std::printf("%s: max stretch %.2f%% after 2 s\n", config.describe().c_str(), 100 * d.maxStretch);
    return 0;
}
