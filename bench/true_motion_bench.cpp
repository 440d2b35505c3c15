// The true motion's integrator as the demo flag's true-motion scene ships it (small_steps with
// max_move = 1 cm, the demo flag's tethers and stretch limit at every substep) on the swung pole
// (swung_pole.h), without air or contact: 30 steps in, then windows of 60 steps, each from the
// same state (put back outside the timing). Arguments: the flag's side and the solver's threads.
// Counter: substeps per step. The rows time the substep's own phases (forces, integration,
// constraints) where the scene's frame times mix them with the air, contact and the host.

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "cloth/constraints.h"
#include "cloth/solver_config.h"
#include "swung_pole.h"

namespace {

constexpr int kSettle = 30, kSteps = 60;

void trueMotion(benchmark::State& bm) {
    cloth::HangingFlag flag = bench::flagOfSize(static_cast<int>(bm.range(0)));
    cloth::SolverConfig config;
    // parallel_from=0: on the threads at 33x33 too, where the scenes' solver steps on one
    const std::string spec = "small_steps:max_move=0.01,parallel_from=0,threads=" + std::to_string(bm.range(1));
    std::string error;
    if (!cloth::parseSolverConfig(spec, config, &error)) return bm.SkipWithError(error.c_str());
    auto solver = cloth::makeSolver(config);
    cloth::Constraints constraints;
    cloth::parseConstraints("tether=0.02,stretch_limit=0.1,stretch_passes=4", constraints, nullptr);
    solver->setConstraints(constraints);
    std::vector<cloth::StepInput> inputs;  // made before the timing
    for (int s = 0; s < kSettle + kSteps; ++s) inputs.push_back(bench::inputOfStep(flag, bench::Pole::Swung, s));
    for (int s = 0; s < kSettle; ++s) solver->step(flag.model, cloth::Environment{}, flag.state, inputs[std::size_t(s)]);
    const cloth::State start = flag.state;
    double substeps = 0;
    while (bm.KeepRunningBatch(kSteps)) {
        bm.PauseTiming();
        flag.state = start;
        bm.ResumeTiming();
        for (int s = kSettle; s < kSettle + kSteps; ++s) {
            substeps += solver->step(flag.model, cloth::Environment{}, flag.state, inputs[std::size_t(s)]).iterations;
            benchmark::ClobberMemory();
        }
    }
    bm.counters["substeps/step"] = substeps / double(bm.iterations());
}

}  // namespace

BENCHMARK(trueMotion)->Args({33, 1})->Args({33, 2})->Args({65, 1})->Args({65, 2})->Unit(benchmark::kMicrosecond)->UseRealTime();
