// Cloth step per solver and size, fast against reference, float against double, 1 and 2
// threads, and Bullet's btSoftBody on the same mesh. Run through `tools/run bench`.
//
// Every benchmark steps a 33x33-style hanging flag (cloth/presets.h) for 30 steps, then times
// steps 31..90 in whole windows of kWindow steps (the state is put back between windows, outside
// the timing): every row of a size times the same motion, however long it runs, so an adaptive
// solver's cycle count does not depend on how many iterations Google Benchmark picks. The pole
// is still (the flag has settled by step 50: nothing happens in most of the window) or, in the
// `swung_` rows, moves on a circle at 2 Hz (2.4 g), so that the flag flaps and stretches in every
// timed step, as on the demo's vehicle. Counters: particle_steps/s, iterations/step (solver
// iterations; multigrid: CG iterations, one cycle each), and for the strain comparison the max
// stretch after 240 steps at h = 1/240 s on the same pole.

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "cloth/air.h"
#include "cloth/diagnostics.h"
#include "cloth/presets.h"
#include "cloth/solvers/multigrid_settings.h"
#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "cloth/constraints.h"
#include "swung_pole.h"
#ifdef FLAGSIM_HAS_BULLET_PEER
#include "peers/bullet_cloth.h"
#endif

namespace {

using bench::flagOfSize;
using bench::inputOfStep;
using bench::kH;
using bench::Pole;
constexpr int kWindow = 60;  // timed steps before the state is put back

// Multigrid's tuning next to what the study settled (cloth/solver.h, MultigridTuning).
using Tune = void (*)(cloth::MultigridTuning&);
void sweeps22(cloth::MultigridTuning& t) { t.preSweeps = t.postSweeps = 2; }
void underCg(cloth::MultigridTuning& t) { t.krylov = true; }
void globalStop(cloth::MultigridTuning& t) { t.localTolerance = 0; }
void history1(cloth::MultigridTuning& t) { t.startHistory = 1; }
void history3(cloth::MultigridTuning& t) { t.startHistory = 3; }
void vCycles(cloth::MultigridTuning& t) { t.kcycleLevels = 0; }
void kCycle(cloth::MultigridTuning& t) { t.kcycleLevels = 1; }
void lag4(cloth::MultigridTuning& t) { t.coarseEvery = 4; }

// A multigrid config's settled tuning changed by `tune`.
void applyTuning(cloth::SolverConfig& config, Tune tune) {
    auto& s = config.get<cloth::MultigridSettings>();
    cloth::MultigridTuning t = cloth::settledTuning(s);
    tune(t);
    s.tuning = t;
}

// Arguments: the flag's side and the thread count (0: a solver without a thread setting).
void stepFlag(benchmark::State& bm, const char* spec, Pole pole, Tune tune = nullptr) {
    cloth::HangingFlag flag = flagOfSize(static_cast<int>(bm.range(0)));
    cloth::SolverConfig config;
    std::string error;
    if (!cloth::parseSolverConfig(spec, config, &error) ||
        (bm.range(1) > 0 && !cloth::setSolverParameter(config, "threads", std::to_string(bm.range(1)), &error))) {
        bm.SkipWithError(("solver spec '" + std::string(spec) + "': " + error).c_str());
        return;
    }
    if (tune) applyTuning(config, tune);
    auto solver = cloth::makeSolver(config);
    cloth::Environment env;
    constexpr int kWarmUp = 30;
    std::vector<cloth::StepInput> inputs;  // made before the timing
    for (int s = 0; s < kWarmUp + kWindow; ++s) inputs.push_back(inputOfStep(flag, pole, s));
    for (int s = 0; s < kWarmUp; ++s) solver->step(flag.model, env, flag.state, inputs[s]);
    const cloth::State start = flag.state;
    double iterations = 0;
    while (bm.KeepRunningBatch(kWindow)) {  // whole windows only, each from the same state
        bm.PauseTiming();
        flag.state = start;
        bm.ResumeTiming();
        for (int s = kWarmUp; s < kWarmUp + kWindow; ++s) {
            iterations += solver->step(flag.model, env, flag.state, inputs[s]).iterations;
            benchmark::ClobberMemory();
        }
    }
    bm.counters["particle_steps/s"] =
        benchmark::Counter(double(flag.model.particleCount()) * bm.iterations(), benchmark::Counter::kIsRate);
    // Solver iterations per step (multigrid: CG iterations, one cycle each), so that cost per iteration can be compared
    // across sizes.
    bm.counters["iterations/step"] = iterations / double(bm.iterations());
    // Strain after a fixed 1 s of simulated time from the start (same for every solver).
    cloth::HangingFlag fresh = flagOfSize(static_cast<int>(bm.range(0)));
    auto again = cloth::makeSolver(config);
    for (int s = 0; s < 240; ++s) again->step(fresh.model, env, fresh.state, inputOfStep(fresh, pole, s));
    bm.counters["max_stretch"] = cloth::measure(fresh.model, env, fresh.state, true).maxStretch;
}

void sizes(benchmark::internal::Benchmark* b) {
    for (int n : {17, 33, 65, 129, 257}) b->Args({n, 1});
    for (int n : {65, 129, 257}) b->Args({n, 2});
}

// The sizes of the multigrid goals (docs/multigrid.md): 33 and 129 for cost, 257 for scaling.
void goalSizes(benchmark::internal::Benchmark* b) {
    for (int n : {33, 129, 257}) b->Args({n, 1});
}

// The air on a fallen flag in a 10 m/s side wind: the forces alone (explicit air), or also their
// velocity Jacobian and the damping blocks that implicit air adds to W. Argument: the flag's side.
void airForces(benchmark::State& bm, bool implicit) {
    cloth::HangingFlag flag = flagOfSize(static_cast<int>(bm.range(0)));
    auto solver = cloth::makeSolver(cloth::SolverConfig{});
    cloth::StepInput input;
    input.h = kH;
    input.pins = flag.pins;
    for (int s = 0; s < 30; ++s) solver->step(flag.model, cloth::Environment{}, flag.state, input);
    cloth::AirParams air;
    air.wind = cloth::Vec3(3, 0, 10);
    cloth::Points f(3, flag.model.particleCount());
    std::vector<cloth::Mat3> jacobian, damping;
    for (auto _ : bm) {
        f.setZero();
        cloth::addAirForces(flag.model, flag.state, air, f, implicit ? &jacobian : nullptr);
        if (implicit) cloth::airDamping(jacobian, damping);
        benchmark::DoNotOptimize(f.data());
        benchmark::ClobberMemory();
    }
    bm.counters["particle_steps/s"] =
        benchmark::Counter(double(flag.model.particleCount()) * bm.iterations(), benchmark::Counter::kIsRate);
}

// One call of the stretch limit (stretch_limit=0.1) on a flag stretched over all of its area, as
// on the vehicle, where most of the flag sits at the limit: 60 steps of the demo's solver on the
// swung pole, then every particle's offset from the pole's top pin scaled by 1.12. The state is
// put back before every call, outside the timing. Arguments: the flag's side and the passes.
// Counter: corrections per call.
void stretchLimit(benchmark::State& bm) {
    cloth::HangingFlag flag = flagOfSize(static_cast<int>(bm.range(0)));
    auto solver = bench::demoSolver("tether=0.02,stretch_limit=0.1,stretch_passes=4");
    bench::run(*solver, flag, Pole::Swung, 0, 60);
    const cloth::Vec3 top = flag.state.x.col(flag.pins.front().particle);
    for (cloth::Index i = 0; i < flag.model.particleCount(); ++i)
        flag.state.x.col(i) = top + 1.12 * (flag.state.x.col(i) - top);
    std::vector<std::uint8_t> pinned(flag.model.particleCount(), 0);
    for (const cloth::Pin& p : flag.pins) pinned[p.particle] = 1;
    const cloth::State start = flag.state;
    double corrections = 0;
    cloth::StretchLimit limit;  // its check table built once, as a solver keeps it
    for (auto _ : bm) {
        bm.PauseTiming();
        flag.state = start;
        bm.ResumeTiming();
        corrections += limit.apply(flag.model, pinned, 0.1, static_cast<int>(bm.range(1)), kH, flag.state);
        benchmark::ClobberMemory();
    }
    bm.counters["corrections/call"] = corrections / double(bm.iterations());
}

#ifdef FLAGSIM_HAS_BULLET_PEER
void stepBullet(benchmark::State& bm) {
    cloth::HangingFlag flag = flagOfSize(static_cast<int>(bm.range(0)));
    const int iterations = static_cast<int>(bm.range(1));
    peer::BulletCloth bullet(flag.model, flag.state, flag.pins, iterations);
    for (int s = 0; s < 30; ++s) bullet.step(kH);
    for (auto _ : bm) bullet.step(kH);
    bm.counters["particle_steps/s"] =
        benchmark::Counter(double(flag.model.particleCount()) * bm.iterations(), benchmark::Counter::kIsRate);
    cloth::HangingFlag fresh = flagOfSize(static_cast<int>(bm.range(0)));
    peer::BulletCloth again(fresh.model, fresh.state, fresh.pins, iterations);
    for (int s = 0; s < 240; ++s) again.step(kH);
    again.positions(fresh.state.x);
    bm.counters["max_stretch"] = cloth::measure(fresh.model, cloth::Environment{}, fresh.state, true).maxStretch;
}
#endif

}  // namespace

BENCHMARK_CAPTURE(stepFlag, kangcho_fast_double, "kangcho", Pole::Still)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, kangcho_fast_float, "kangcho:precision=float", Pole::Still)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, kangcho_gather_double, "kangcho:impl=gather", Pole::Still)->Args({33, 1})->Args({129, 1})->Args({129, 2})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, kangcho_reference, "kangcho:impl=reference", Pole::Still)->Args({33, 1})->Args({129, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, kangcho_4_iterations, "kangcho:iterations=4", Pole::Still)->Args({33, 1})->Unit(benchmark::kMicrosecond);
// Multigrid on the same system: one fixed V-cycle, two, and the adaptive default (until the
// relative residual is under 1.5e-3, K-cycles on level 1, at most 16), next to the paper's step.
BENCHMARK_CAPTURE(stepFlag, multigrid_1_cycle_double, "multigrid:cycles=1", Pole::Still)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, multigrid_1_cycle_float, "multigrid:cycles=1,precision=float", Pole::Still)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, multigrid_2_cycles_double, "multigrid:cycles=2", Pole::Still)->Apply(sizes)->Unit(benchmark::kMicrosecond);
// V(2,2): two smoothing sweeps before and after the coarse correction (the default is V(1,1)).
BENCHMARK_CAPTURE(stepFlag, multigrid_1_cycle_v22_double, "multigrid:cycles=1", Pole::Still, sweeps22)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, multigrid_adaptive_v22_double, "multigrid", Pole::Still, sweeps22)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, multigrid_adaptive_double, "multigrid", Pole::Still)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, multigrid_adaptive_float, "multigrid:precision=float", Pole::Still)->Apply(sizes)->Unit(benchmark::kMicrosecond);
// The goal rows again on the swung pole, where the flag moves in every timed step.
BENCHMARK_CAPTURE(stepFlag, swung_kangcho_fast_double, "kangcho", Pole::Swung)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_kangcho_fast_float, "kangcho:precision=float", Pole::Swung)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_1_cycle_double, "multigrid:cycles=1", Pole::Swung)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_1_cycle_float, "multigrid:cycles=1,precision=float", Pole::Swung)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
// One cycle under CG (its one iteration scales the cycle by a step length; a fixed cycle runs
// alone by default: the step length moved the vehicle path's solve error by -4% to +7% at one
// product with W more, docs/study/multigrid_start.csv).
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_1_cycle_cg_double, "multigrid:cycles=1", Pole::Swung, underCg)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_double, "multigrid", Pole::Swung)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_float, "multigrid:precision=float", Pole::Swung)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
// Mixed precision: the cycles in float under the double CG.
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_mixed, "multigrid:precision=mixed", Pole::Swung)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_1_cycle_mixed, "multigrid:cycles=1,precision=mixed", Pole::Swung)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
// The adaptive stop on the relative residual alone, without the default's local test
// (docs/multigrid.md, "The stopping test"; docs/study/multigrid_local_ensemble.csv).
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_global_double, "multigrid", Pole::Swung, globalStop)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_global_mixed, "multigrid:precision=mixed", Pole::Swung, globalStop)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
// The start from the last solve's dv alone (scaled to the least error), and from the last three:
// the default combines the last two (docs/multigrid.md, "Start"; docs/study/multigrid_start.csv).
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_history1_double, "multigrid", Pole::Swung, history1)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_history3_double, "multigrid", Pole::Swung, history3)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
// V-cycles to 1e-3 instead of the default's K-cycle on level 1 to 1.5e-3, and one K-cycle (the
// adaptive default runs K-cycles, a fixed count V-cycles): docs/study/multigrid_kcycle.csv.
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_v_double, "multigrid:tolerance=1e-3", Pole::Swung, vCycles)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_v_float, "multigrid:tolerance=1e-3,precision=float", Pole::Swung, vCycles)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_1_cycle_k1_double, "multigrid:cycles=1", Pole::Swung, kCycle)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
// The coarse operators rebuilt every 4th step and reused in between (tuning coarseEvery = 4): on the
// still pole 10-18% cheaper at the same cycle count; on the swung pole the cycles at 129x129 rise
// from 7.8 to 13.4, which is why the default rebuilds them every step (docs/multigrid.md).
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_lag4_double, "multigrid", Pole::Swung, lag4)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, swung_multigrid_adaptive_lag4_float, "multigrid:precision=float", Pole::Swung, lag4)->Apply(goalSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, exact_multigrid, "exact:method=multigrid", Pole::Still)->Args({33, 0})->Args({129, 0})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, exact_cholesky, "exact", Pole::Still)->Args({17, 0})->Args({33, 0})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, cg_1e-6, "cg:tolerance=1e-6", Pole::Still)->Args({33, 0})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(stepFlag, explicit_1_substep, "explicit", Pole::Still)->Args({33, 0})->Unit(benchmark::kMicrosecond);
#ifdef FLAGSIM_HAS_BULLET_PEER
// Bullet's default (1 position iteration, the same count as the paper's one Jacobi sweep) and more.
BENCHMARK(stepBullet)->Args({33, 1})->Args({33, 4})->Args({33, 10})->Args({129, 1})->Unit(benchmark::kMicrosecond);
#endif

BENCHMARK_CAPTURE(airForces, explicit, false)->Arg(33)->Arg(129)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(airForces, implicit, true)->Arg(33)->Arg(129)->Unit(benchmark::kMicrosecond);
BENCHMARK(stretchLimit)->Args({33, 4})->Args({65, 4})->Args({129, 4})->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
