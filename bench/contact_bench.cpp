// One application of contact (cloth/contact.h) to one step of the flag on the swung pole
// (swung_pole.h): the paper's step with the demo's constraints, 60 steps in, then the step from
// 60 to 61, in the pole's frame, with the pole's capsule as the solid and self-contact at the
// thickness and sub-interval of the shipped scenes (1.5 cm, 2.5 mm). The state is put back before
// every call, outside the timing.
//   - `hanging`: the same on a pole that stands still, where the flag has settled (no pairs: the
//     broad phase's passes over the whole flag alone, the least an application costs);
//   - `swung`: the flag as it flaps (few self pairs, as in most of the true motion's applications:
//     the broad phase's passes over the whole flag are most of the cost);
//   - `folded`: the same step with the flag's outer half laid back over its inner half, 3 cm
//     above it and moving with it (hundreds of pairs at every sub-interval, as in the demo's
//     folds).
// Argument: the flag's side. Counters per call: self pairs, sub-intervals and the broad phase's
// microseconds (ContactReport::broadPhaseMs). The `_2threads` rows run the same with a pool of two
// threads as the application's parallel loops (ContactStage::apply's `loops`).

#include <benchmark/benchmark.h>

#include <vector>

#include "cloth/contact.h"
#include "cloth/thread_pool.h"
#include "swung_pole.h"

namespace {

constexpr int kStart = 60;
constexpr double kFoldGap = 0.03;  // m between the folded halves

// Column c > m of every row takes the place of column 2m - c, kFoldGap above it in z.
void fold(const cloth::Model& model, cloth::Points& x) {
    const int nx = model.gridNx(), ny = model.gridNy(), m = (nx - 1) / 2;
    for (int r = 0; r < ny; ++r)
        for (int c = m + 1; c < nx; ++c) x.col(r * nx + c) = x.col(r * nx + 2 * m - c) + cloth::Vec3(0, 0, kFoldGap);
}

enum class Case { Hanging, Swung, Folded };

void contactApply(benchmark::State& bm, Case what, int threads) {
    const bench::Pole motion = what == Case::Hanging ? bench::Pole::Still : bench::Pole::Swung;
    cloth::HangingFlag flag = bench::flagOfSize(static_cast<int>(bm.range(0)));
    auto solver = bench::demoSolver("tether=0.02,stretch_limit=0.1");
    bench::run(*solver, flag, motion, 0, kStart);
    const cloth::Points start = flag.state.x;
    bench::run(*solver, flag, motion, kStart, kStart + 1);
    cloth::Points xStart = start;
    cloth::State end = flag.state;
    if (what == Case::Folded) fold(flag.model, xStart), fold(flag.model, end.x), fold(flag.model, end.v);

    std::vector<std::uint8_t> pinned(flag.model.particleCount(), 0);
    for (const cloth::Pin& p : flag.pins) pinned[p.particle] = 1;
    cloth::RigidFrame from, to;
    if (motion == bench::Pole::Swung) from.position = bench::poleOffset(kStart), to.position = bench::poleOffset(kStart + 1);
    cloth::Collider pole;  // the pole in its own frame: the pins on its surface
    pole.shape = cloth::Collider::Shape::Capsule;
    pole.radius = 0.03, pole.center = cloth::Vec3(-pole.radius, 1.5, 0), pole.halfExtents.x() = 0.55;
    cloth::ContactSettings settings;
    settings.enabled = true, settings.thickness = 0.015;

    cloth::ContactStage stage;  // its broad phase's tree built once, as a cloth keeps it
    cloth::ThreadPool pool(threads);
    cloth::ContactReport sum;
    for (auto _ : bm) {
        bm.PauseTiming();
        flag.state = end;
        bm.ResumeTiming();
        sum += stage.apply(flag.model, pinned, xStart, flag.state, from, to, {pole}, settings, bench::kH,
                           threads > 1 ? &pool : nullptr);
        benchmark::ClobberMemory();
    }
    const double calls = double(sum.applications);
    bm.counters["self_pairs/call"] = double(sum.selfPairs) / calls;
    bm.counters["subintervals/call"] = double(sum.subintervals) / calls;
    bm.counters["broad_phase_us/call"] = 1000 * sum.broadPhaseMs / calls;
}

}  // namespace

BENCHMARK_CAPTURE(contactApply, hanging, Case::Hanging, 1)->Arg(33)->Arg(65)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contactApply, swung, Case::Swung, 1)->Arg(33)->Arg(65)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contactApply, folded, Case::Folded, 1)->Arg(33)->Arg(65)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contactApply, hanging_2threads, Case::Hanging, 2)->Arg(65)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contactApply, swung_2threads, Case::Swung, 2)->Arg(65)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(contactApply, folded_2threads, Case::Folded, 2)->Arg(65)->Unit(benchmark::kMicrosecond);
