// The roofline of this machine and where the cloth's kernels sit under it (Williams, Waterman &
// Patterson 2009: attainable = min(peak flops, bandwidth x flops per byte)).
//
// The roofs, on one thread and on two:
//   roof/peak_fma       8-wide float fused multiply-adds, 10 independent chains (2 flops each)
//   roof/peak_mul_add   the same as a multiply and an add: the library is built with
//                       -ffp-contract=off (the same bits from its AVX2 and baseline clones), so
//                       its kernels can reach this one, half the FMA roof
//   roof/stream_triad   a[i] = b[i] + s c[i] over 3 x 32 MiB (12 bytes and 2 flops per element)
// The kernels at 33x33 (1,089 particles, 6,176 springs in 6 families, 2,048 triangles), each
// with its flops and bytes per call as counters (flops_per_s, bytes_per_s: Google Benchmark
// divides by the time). Flops are counted from each kernel's source, per element, one per add,
// multiply, divide, square root or select; bytes are the arrays a call reads and writes once (its
// compulsory traffic: at 33x33 every kernel's data fits in L2, so the memory roof never binds).
// tools/roofline_table.py turns a run into the table of docs/performance.md.

#include <benchmark/benchmark.h>
#include <immintrin.h>

#include <thread>
#include <vector>

#include "cloth/paper_step.h"
#include "cloth/air.h"
#include "cloth/constraints.h"
#include "cloth/presets.h"
#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "cloth/system.h"

namespace {

constexpr double kTick = 1.0 / 240;
constexpr int kChains = 10;

// kChains independent accumulators, so the FMA (or multiply and add) pipes never wait on a result.
__attribute__((target("avx2,fma"), noinline)) float fmaChains(long iterations, bool fused) {
    __m256 acc[kChains];
    for (int c = 0; c < kChains; ++c) acc[c] = _mm256_set1_ps(float(c) * 1e-3f);
    const __m256 a = _mm256_set1_ps(0.999999f), b = _mm256_set1_ps(1e-7f);
    for (long i = 0; i < iterations; ++i)
        for (int c = 0; c < kChains; ++c) acc[c] = fused ? _mm256_fmadd_ps(acc[c], a, b) : _mm256_add_ps(_mm256_mul_ps(acc[c], a), b);
    __m256 sum = acc[0];
    for (int c = 1; c < kChains; ++c) sum = _mm256_add_ps(sum, acc[c]);
    float out[8];
    _mm256_storeu_ps(out, sum);
    return out[0];
}

void peak(benchmark::State& bm, bool fused) {
    constexpr long kIterations = 1 << 20;
    for (auto _ : bm) {
        long iterations = kIterations;
        benchmark::DoNotOptimize(iterations);  // not a constant: every call runs its loop
        benchmark::DoNotOptimize(fmaChains(iterations, fused));
    }
    // Per thread: Google Benchmark sums a counter over the threads and multiplies an
    // iteration-invariant one by every thread's iterations, so each thread gives its share.
    const double flops = double(kIterations) * kChains * 8 * 2 / bm.threads();  // 8 lanes, a multiply and an add
    bm.counters["flops_per_s"] = benchmark::Counter(flops, benchmark::Counter::kIsIterationInvariantRate);
}

void streamTriad(benchmark::State& bm) {
    static const std::size_t n = (32u << 20) / sizeof(float);
    static std::vector<float> a(n, 1), b(n, 2), c(n, 3);  // shared: threads split the range
    const std::size_t begin = n * std::size_t(bm.thread_index()) / std::size_t(bm.threads()),
                      end = n * std::size_t(bm.thread_index() + 1) / std::size_t(bm.threads());
    for (auto _ : bm) {
        for (std::size_t i = begin; i < end; ++i) a[i] = b[i] + 3.0f * c[i];
        benchmark::ClobberMemory();
    }
    const double elements = double(end - begin) / bm.threads();  // summed over threads: see peak()
    bm.counters["bytes_per_s"] = benchmark::Counter(12 * elements, benchmark::Counter::kIsIterationInvariantRate);
    bm.counters["flops_per_s"] = benchmark::Counter(2 * elements, benchmark::Counter::kIsIterationInvariantRate);
}

void roofCounters(benchmark::State& bm, double flopsPerCall, double bytesPerCall) {
    bm.counters["flops_per_s"] = benchmark::Counter(flopsPerCall, benchmark::Counter::kIsIterationInvariantRate);
    bm.counters["bytes_per_s"] = benchmark::Counter(bytesPerCall, benchmark::Counter::kIsIterationInvariantRate);
}

// The stiff flag (k = 1e4 N/m) at 33x33 after 30 steps of the paper's step in a side wind.
struct Flag33 {
    cloth::HangingFlag flag;
    cloth::AirParams air;
    Flag33() : flag(make()) {
        air.wind = cloth::Vec3(3, 0, 10);
        auto solver = cloth::makeSolver(cloth::SolverConfig{});
        for (int s = 0; s < 30; ++s) solver->step(flag.model, {}, flag.state, input());
    }
    static cloth::HangingFlag make() {
        cloth::HangingFlagDesc d;
        d.stiffness = {1e4, 1e4, 1e3};
        return cloth::makeHangingFlag(d);
    }
    cloth::StepInput input() const {
        cloth::StepInput in;
        in.h = kTick;
        in.pins = flag.pins;
        return in;
    }
};

std::unique_ptr<cloth::Solver> solverOf(const char* spec) {
    cloth::SolverConfig c;
    cloth::parseSolverConfig(spec, c, nullptr);
    return cloth::makeSolver(c);
}

// `spec`'s solver with the constraints of `constraints` (a --constraints spec), or none when null.
std::unique_ptr<cloth::Solver> constrainedSolverOf(const char* spec, const char* constraints) {
    auto solver = solverOf(spec);
    if (constraints) {
        cloth::Constraints c;
        cloth::parseConstraints(constraints, c, nullptr);
        solver->setConstraints(c);
    }
    return solver;
}

// One step of `spec` per iteration, from the same state each time (put back outside the timing).
// Counters are per call: `calls` kernel calls per step (substeps, passes, iterations); a row that
// counts its flops itself passes 0 flops and bytes and gets no rates.
void step(benchmark::State& bm, const char* spec, bool air, double flopsPerCall, double bytesPerCall, int calls,
          const char* constraints = nullptr) {
    Flag33 f;
    auto solver = constrainedSolverOf(spec, constraints);
    cloth::StepInput in = f.input();
    if (air) in.air = &f.air;
    const cloth::State start = f.flag.state;
    for (auto _ : bm) {
        bm.PauseTiming();
        f.flag.state = start;
        bm.ResumeTiming();
        solver->step(f.flag.model, {}, f.flag.state, in);
        benchmark::ClobberMemory();
    }
    if (flopsPerCall > 0 || bytesPerCall > 0) roofCounters(bm, flopsPerCall * calls, bytesPerCall * calls);
    bm.counters["calls_per_step"] = calls;
}

// Per element counts at 33x33: n particles, springs s, triangles t.
constexpr double kN = 1089, kS = 6176, kT = 2048;

// small_steps, one substep: springs 16 flops each (difference 3, length 6, force 7), the air 61 per
// triangle and 12 per quad's corners, the integration 78 per particle (12 spring ends and 4
// corners gathered, acceleration, velocity, position); bytes: positions and velocities read and
// written, per family and quad 3 floats written and read back.
constexpr double kSmallStepsFlops = 16 * kS + 61 * kT + 12 * kN + 78 * kN;
constexpr double kSmallStepsBytes = 4 * (12 * kN + 2 * 3 * 6 * kN + 2 * 3 * 4 * kN);
// explicit (double): the same springs scattered to both ends (16 + 6 each), gravity and the
// integration 15 per particle; the air is the caller's.
constexpr double kExplicitFlops = 22 * kS + 15 * kN;
constexpr double kExplicitBytes = 8 * (2 * 6 * kN + 3 * kN) + 32 * kS;
// The air (double): 61 per triangle, 3 per corner sum; with its blocks, the 3x3 velocity
// derivative per triangle (about 110: five coefficients, nine entries of five terms) summed per
// particle (9 per corner), and per particle the damping's closed form (about 150: the
// eigenvalues, a null vector, the outer product).
constexpr double kAirFlops = 61 * kT + 9 * kT, kAirBytes = 8 * (6 * kN + 3 * kN) + 24 * kT;
constexpr double kAirBlockFlops = kAirFlops + 110 * kT + 27 * kT + 150 * kN, kAirBlockBytes = kAirBytes + 8 * 9 * (kT + 2 * kN);
// The springs' forces and Jacobian blocks assembled (double, cloth::buildSystem, what exact, cg and
// chebyshev solve): per spring the force (16) and its block J = a I + b u u^T (about 20), added
// into W_ii of both ends and into the right-hand side (about 60); per particle W_ii's inverse and
// the rest of b (about 80).
constexpr double kSystemFlops = 96 * kS + 80 * kN, kSystemBytes = 8 * (9 * kS + 2 * 9 * kN + 12 * kN);
// A pass of the stretch limit (double): per spring the check (9 flops) on both ends' positions and
// its table row; the few corrections are not counted.
constexpr double kStretchFlops = 9 * kS, kStretchBytes = 8 * 6 * kS + 16 * kS;
// The paper's step in float (stencil): the spring terms 20 per spring, the particle pass about
// 600 per particle (12 spring sides of force and W_ii, W_ii's inverse, dv(0), the sweep's J dv).
constexpr double kPaperFlops = 20 * kS + 600 * kN, kPaperBytes = 4 * (6 * 6 * kN + 40 * kN);
// xpbd, one pass: per spring a constraint projection of about 40 flops, reading and writing both
// ends.
constexpr double kXpbdFlops = 40 * kS, kXpbdBytes = 8 * 12 * kS;

// The true motion's constraints after each substep (tethers at 2%, the stretch limit at 10% in four
// passes), as small_steps runs them: the float test of every spring slot of the six families (9
// flops: difference, squared length, comparison) and of every particle against its tether's anchor
// (9), on positions (12 bytes a particle), each slot's listed square and its flag (5 bytes), an
// anchor, its square and a flag per particle (9). On this flag nothing is over a bound, as in most
// of the true motion's substeps, so nothing is corrected: the row is the check and its collection.
// Its counters are per call, not rates: the constraints' time is this row's less
// small_steps_substep_64's (tools/roofline_table.py).
constexpr double kCheckFlops = 6 * 9 * kN + 9 * kN, kCheckBytes = 12 * kN + 6 * 5 * kN + 9 * kN;

void smallStepsSubstep(benchmark::State& bm) { step(bm, "small_steps:substeps=64", true, kSmallStepsFlops, kSmallStepsBytes, 64); }
constexpr const char* kTrueMotionConstraints = "tether=0.02,stretch_limit=0.1,stretch_passes=4";

// How far the constraints move any particle in one step of the row below (0: it times the check).
double movedByConstraints() {
    Flag33 with, without;
    cloth::StepInput in = with.input();
    in.air = &with.air;
    auto a = constrainedSolverOf("small_steps:substeps=64", kTrueMotionConstraints), b = solverOf("small_steps:substeps=64");
    a->step(with.flag.model, {}, with.flag.state, in);
    b->step(without.flag.model, {}, without.flag.state, in);
    return (with.flag.state.x - without.flag.state.x).cwiseAbs().maxCoeff();
}

void smallStepsConstrained(benchmark::State& bm) {
    step(bm, "small_steps:substeps=64", true, 0, 0, 64, kTrueMotionConstraints);
    bm.counters["moved_by_constraints"] = movedByConstraints();
    bm.counters["check_flops_per_call"] = kCheckFlops;
    bm.counters["check_bytes_per_call"] = kCheckBytes;
}
void explicitSubstep(benchmark::State& bm) { step(bm, "explicit:substeps=64", false, kExplicitFlops, kExplicitBytes, 64); }
void paperStepFloat(benchmark::State& bm) { step(bm, "kangcho:precision=float", false, kPaperFlops, kPaperBytes, 1); }
void xpbdPass(benchmark::State& bm) { step(bm, "xpbd", false, kXpbdFlops, kXpbdBytes, 1); }

// A step of converged BDF2 (newton) per iteration, on one thread and on two (wall clock); the
// counter is per Newton iteration (its GMRES iterations, each a product of the step's derivative
// and a multigrid cycle, with the residual at each iterate), and linear_per_step counts those
// GMRES iterations. Its flops are not counted: the table gives its time only.
void newtonIteration(benchmark::State& bm, const char* spec) {
    Flag33 f;
    auto solver = solverOf(spec);
    cloth::StepInput in = f.input();
    in.air = &f.air;
    const cloth::State start = f.flag.state;
    double iterations = 0, linear = 0;
    for (auto _ : bm) {
        bm.PauseTiming();
        f.flag.state = start;
        solver->resetHistory();
        bm.ResumeTiming();
        const auto r = solver->step(f.flag.model, {}, f.flag.state, in);
        iterations += r.iterations;
        linear += r.linearIterations;
        benchmark::ClobberMemory();
    }
    bm.counters["calls_per_step"] = iterations / double(bm.iterations());
    bm.counters["linear_per_step"] = linear / double(bm.iterations());
}

void springSystem(benchmark::State& bm) {
    Flag33 f;
    const cloth::StepInput in = f.input();
    const cloth::Environment env;
    cloth::LinearSystem sys;
    for (auto _ : bm) {
        cloth::buildSystem({f.flag.model, env, f.flag.state, in}, sys);
        benchmark::ClobberMemory();
    }
    roofCounters(bm, kSystemFlops, kSystemBytes);
}

// Four passes of the stretch limit at 10% over the flag stretched 12% from the pole top.
void stretchPass(benchmark::State& bm) {
    Flag33 f;
    const cloth::Vec3 top = f.flag.state.x.col(f.flag.pins.front().particle);
    for (cloth::Index i = 0; i < f.flag.model.particleCount(); ++i)
        f.flag.state.x.col(i) = top + 1.12 * (f.flag.state.x.col(i) - top);
    std::vector<std::uint8_t> pinned(f.flag.model.particleCount(), 0);
    for (const cloth::Pin& p : f.flag.pins) pinned[p.particle] = 1;
    const cloth::State start = f.flag.state;
    cloth::StretchLimit limit;
    for (auto _ : bm) {
        bm.PauseTiming();
        f.flag.state = start;
        bm.ResumeTiming();
        limit.apply(f.flag.model, pinned, 0.1, 4, kTick, f.flag.state);
        benchmark::ClobberMemory();
    }
    roofCounters(bm, 4 * kStretchFlops, 4 * kStretchBytes);
    bm.counters["calls_per_step"] = 4;
}

void air(benchmark::State& bm, bool blocks) {
    Flag33 f;
    cloth::Points force(3, f.flag.model.particleCount());
    std::vector<cloth::Mat3> jacobian, damping;
    for (auto _ : bm) {
        force.setZero();
        cloth::addAirForces(f.flag.model, f.flag.state, f.air, force, blocks ? &jacobian : nullptr);
        if (blocks) cloth::airDamping(jacobian, damping);
        benchmark::ClobberMemory();
    }
    roofCounters(bm, blocks ? kAirBlockFlops : kAirFlops, blocks ? kAirBlockBytes : kAirBytes);
}

}  // namespace

BENCHMARK_CAPTURE(peak, fma, true)->Name("roof/peak_fma")->Threads(1)->Threads(2)->UseRealTime();
BENCHMARK_CAPTURE(peak, mul_add, false)->Name("roof/peak_mul_add")->Threads(1)->Threads(2)->UseRealTime();
BENCHMARK(streamTriad)->Name("roof/stream_triad")->Threads(1)->Threads(2)->UseRealTime();
BENCHMARK(smallStepsSubstep)->Name("kernel/small_steps_substep_64/33")->Unit(benchmark::kMicrosecond);
BENCHMARK(smallStepsConstrained)->Name("kernel/small_steps_constraints_64/33")->Unit(benchmark::kMicrosecond);
BENCHMARK(explicitSubstep)->Name("kernel/explicit_substep_64/33")->Unit(benchmark::kMicrosecond);
BENCHMARK(paperStepFloat)->Name("kernel/paper_step_float/33")->Unit(benchmark::kMicrosecond);
BENCHMARK(xpbdPass)->Name("kernel/xpbd_pass/33")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(air, forces, false)->Name("kernel/air/33")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(air, blocks, true)->Name("kernel/air_with_blocks/33")->Unit(benchmark::kMicrosecond);
BENCHMARK(springSystem)->Name("kernel/spring_system/33")->Unit(benchmark::kMicrosecond);
BENCHMARK(stretchPass)->Name("kernel/stretch_limit_pass/33")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(newtonIteration, one, "newton:integrator=bdf2")->Name("kernel/newton_iteration/33")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(newtonIteration, two, "newton:integrator=bdf2,threads=2")
    ->Name("kernel/newton_iteration/33/2_threads")
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
