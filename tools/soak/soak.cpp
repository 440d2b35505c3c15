// The soak's segments, its memory verdict and its report.

#include "soak.h"

#include <SDL.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <set>
#include <random>

#include <nlohmann/json.hpp>

#include "engine/files/atomic_file.h"
#include "engine/runtime.h"
#include "engine/scene/scene.h"

namespace soak {

namespace {

const std::vector<std::string> kWindowScenes = {"flag_vehicle", "flag_vehicle_stiff", "flag_vehicle_true_motion",
                                                "flag_vehicle_hd", "hanging_flag", "vehicle_only"};

// Memory is judged between segments, when the segment's runtimes are gone (and the freed heap is
// returned): after the warm-up, no such floor more than 5% above the warm-up's highest floor. A
// leak raises the floor; a heavy solver's working set (an exact Cholesky factor at 65x65 adds
// some 30 MiB) only raises the peak while it runs, so the peaks are reported, not judged. Empty
// when it holds, or when the soak ended before its warm-up did (the report says so).
std::string memoryVerdict(const SoakState& state, nlohmann::json& report) {
    auto peaks = [&state](const std::vector<std::pair<double, long>>& samples) {
        long warm = 0, late = 0;
        for (const auto& [minutes, kib] : samples) {
            long& peak = state.warmedUp >= 0 && minutes > state.warmedUp ? late : warm;
            peak = std::max(peak, kib);
        }
        return std::pair{warm, late};
    };
    const auto [warm, late] = peaks(state.floors);
    const auto [warmPeak, latePeak] = peaks(state.memory);
    report.update({{"resident_kib_warmup_floor", warm}, {"resident_kib_after_warmup_floor", late},
                   {"resident_kib_warmup_peak", warmPeak}, {"resident_kib_after_warmup_peak", latePeak},
                   {"warmup_ended_minute", state.warmedUp}, {"resident_kib_series", state.memory}});
    if (state.warmedUp < 0 || late == 0) {
        std::printf("memory: the soak ended within its warm-up (peak %.0f MiB): not judged\n", warmPeak / 1024.0);
        return {};
    }
    const double growth = double(late - warm) / double(warm);
    report["resident_growth"] = growth;
    std::printf("memory between segments: %.1f MiB in the warm-up, %.1f MiB after it (%+.1f%%); peaks %.1f and %.1f MiB\n",
                warm / 1024.0, late / 1024.0, 100 * growth, warmPeak / 1024.0, latePeak / 1024.0);
    if (growth <= 0.05) return {};
    char buf[160];
    std::snprintf(buf, sizeof buf, "resident memory grew %.1f%% after the warm-up (between segments: %ld KiB, then %ld KiB)",
                  100 * growth, warm, late);
    return buf;
}

nlohmann::json segmentJson(const SegmentPlan& plan, const SegmentResult& r) {
    return {{"index", plan.index},        {"scene", plan.scene},         {"frames", r.frames},
            {"script", plan.script},      {"refusals", r.refusals},      {"flag_failures", r.flagFailures},
            {"first_flag_failure", r.firstFlagFailure}, {"replayed", r.replayed}, {"problem", r.problem},
            {"wall_seconds", r.wallSeconds}};
}

void printSegment(const SegmentPlan& plan, const SegmentResult& r, const SoakState& state) {
    std::printf("[%5.1f min] segment %3d  %-20s %5d frames  %3d refused  %3d flag failures  %s\n", state.minutes(),
                plan.index, std::filesystem::path(plan.scene).stem().c_str(), r.frames, r.refusals, r.flagFailures,
                !r.problem.empty() ? "FAIL" : r.replayed ? "replay: same frames" : "");
    if (!r.firstFlagFailure.empty()) std::printf("             first flag failure: %s\n", r.firstFlagFailure.c_str());
    std::fflush(stdout);
}

nlohmann::json frameTimesJson(const SoakState& state) {
    nlohmann::json j;
    std::printf("%-20s %8s %8s %8s %8s\n", "frame ms", "frames", "p50", "p99", "max");
    for (const auto& [scene, t] : state.frameTimes) {
        std::printf("%-20s %8ld %8.1f %8.1f %8.1f\n", scene.c_str(), t.count(), t.percentile(0.5), t.percentile(0.99),
                    t.max());
        j[scene] = {{"frames", t.count()}, {"p50", t.percentile(0.5)}, {"p99", t.percentile(0.99)}, {"max", t.max()}};
    }
    return j;
}

}  // namespace

int runSoak(const SoakOptions& options) {
    if (SDL_InitSubSystem(SDL_INIT_VIDEO | SDL_INIT_GAMECONTROLLER) != 0) {  // held for the whole soak
        std::fprintf(stderr, "flagsim_soak: SDL could not start: %s\n", SDL_GetError());
        return 1;
    }
    std::filesystem::create_directories(options.outDir);
    const std::string assets = options.assetsDir.empty() ? engine::defaultAssetsDir() : options.assetsDir;
    const std::vector<std::string>& scenes = options.scenes.empty() ? kWindowScenes : options.scenes;
    std::mt19937_64 plans(options.seed * 0x9E3779B97F4A7C15ull + 1);
    VirtualPad pad;
    SoakState state(options, pad);
    nlohmann::json report = {{"seed", options.seed}, {"minutes", options.minutes}, {"plant", options.plant}};
    std::vector<std::string> problems;
    std::vector<std::size_t> order(scenes.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), plans);
    std::set<std::string> seen;
    long frames = 0, refusals = 0, failures = 0;
    for (int k = 0; state.minutes() < options.minutes && problems.empty() && !engine::stopRequested(); ++k) {
        char script[32];
        std::snprintf(script, sizeof script, "segment-%03d.json", k);
        // Every scene once first (the warm-up), in a random order; then any.
        const std::size_t pick = k < int(scenes.size()) ? order[std::size_t(k)] : plans() % scenes.size();
        SegmentPlan plan{k, engine::resolveScenePath(scenes[pick], assets),
                         int(options.segmentFrames / 6 + plans() % (options.segmentFrames * 5 / 6)), (std::filesystem::path(options.outDir) / script).string()};
        const SegmentResult r = runSegment(plan, state);
        state.sampleMemory(true);
        state.floors.push_back(state.memory.back());  // the runtimes are gone: what stays is kept memory
        seen.insert(plan.scene);
        if (state.warmedUp < 0 && state.minutes() >= options.warmupMinutes && seen.size() == scenes.size())
            state.warmedUp = state.minutes();
        frames += r.frames, refusals += r.refusals, failures += r.flagFailures;
        report["segments"].push_back(segmentJson(plan, r));
        printSegment(plan, r, state);
        if (!r.problem.empty()) problems.push_back(r.problem);
    }
    if (std::string m = memoryVerdict(state, report); !m.empty()) problems.push_back(m);
    report["frame_ms"] = frameTimesJson(state);
    report["gestures"] = state.user.counts();
    std::printf("gestures:");
    for (const auto& [kind, n] : state.user.counts()) std::printf(" %s %ld", kind.c_str(), n);
    std::printf("\n");
    report.update({{"frames", frames}, {"refusals", refusals}, {"flag_failures", failures},
                   {"wall_minutes", state.minutes()}, {"problems", problems}});
    std::printf("%ld frames in %.1f min, %ld commands refused, %ld flag failures caught\n", frames, state.minutes(),
                refusals, failures);
    std::string error;
    if (!engine::writeFileAtomically(options.outDir + "/soak.json", report.dump(2) + "\n", &error))
        problems.push_back(error);
    for (const std::string& p : problems) std::printf("FAIL: %s\n", p.c_str());
    if (problems.empty()) std::printf("PASS: no watcher failed (seed %llu)\n", (unsigned long long)options.seed);
    return problems.empty() ? 0 : 1;
}

}  // namespace soak
