// Cloth step per solver and size. Run through `tools/run bench`.

#include <benchmark/benchmark.h>

#include "cloth/presets.h"
#include "cloth/solver.h"

namespace {

void stepFlag(benchmark::State& bm, const char* spec) {
    cloth::HangingFlagDesc d;
    d.nx = d.ny = static_cast<int>(bm.range(0));
    cloth::HangingFlag flag = cloth::makeHangingFlag(d);
    cloth::SolverConfig config;
    cloth::parseSolverConfig(spec, config, nullptr);
    auto solver = cloth::makeSolver(config);
    cloth::Environment env;
    cloth::StepInput input;
    input.h = 1.0 / 60;
    input.pins = flag.pins;
    // Let the flag fall into a typical deformed state before timing.
    for (int s = 0; s < 30; ++s) solver->step(flag.model, env, flag.state, input);
    for (auto _ : bm) {
        solver->step(flag.model, env, flag.state, input);
        benchmark::ClobberMemory();
    }
    bm.counters["particle_steps/s"] = benchmark::Counter(
        double(flag.model.particleCount()) * bm.iterations(), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK_CAPTURE(stepFlag, kangcho_1, "kangcho")->Arg(17)->Arg(33)->Arg(65)->Arg(129)->Arg(257)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, kangcho_4, "kangcho:iterations=4")->Arg(33)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, exact, "exact")->Arg(17)->Arg(33)->Arg(65)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, cg, "cg:tolerance=1e-6")->Arg(33)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, explicit_1, "explicit")->Arg(33)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
