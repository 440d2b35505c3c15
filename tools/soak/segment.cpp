// One segment of the soak: the scene live in a window under the random user, its input recorded;
// then the recording replayed in a window, frame by frame against the live hashes.

#include <SDL.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>

#include "engine/scene/config_error.h"
#include "engine/runtime.h"
#include "soak.h"

namespace soak {

namespace {

using Clock = std::chrono::steady_clock;

// FNV-1a over the frame's 64-bit words (and its tail): any changed pixel changes it.
std::uint64_t hashPixels(const std::vector<std::uint8_t>& p) {
    std::uint64_t h = 1469598103934665603ull, word = 0;
    std::size_t i = 0;
    for (; i + 8 <= p.size(); i += 8) {
        std::memcpy(&word, p.data() + i, 8);
        h = (h ^ word) * 1099511628211ull;
    }
    for (; i < p.size(); ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

engine::RunOptions windowOptions(const SegmentPlan& plan, const SoakOptions& o) {
    engine::RunOptions r;
    r.window = true;
    r.readback = true;
    r.frames = plan.frames;
    r.noProgress = true;
    r.width = o.width, r.height = o.height;
    if (!o.assetsDir.empty()) r.assetsDir = o.assetsDir;
    return r;
}

// The first non-finite value of the flag or the vehicle, named; empty when all are finite.
std::string nonFinite(const engine::Runtime& rt) {
    if (const engine::Flag* flag = rt.flag()) {
        const cloth::State& s = flag->state();
        for (cloth::Index i = 0; i < s.x.cols(); ++i)
            if (!s.x.col(i).allFinite() || !s.v.col(i).allFinite())
                return "flag particle " + std::to_string(i) + " is not finite";
    }
    if (!rt.poleTop().allFinite() || !rt.carrierVelocity().allFinite()) return "the pole (vehicle) is not finite";
    return {};
}

std::string where(const SegmentPlan& plan, const std::string& what) {
    return "segment " + std::to_string(plan.index) + " (" + plan.scene + "): " + what;
}

// --plant: the faults the watchers must catch, in the first segment.
void plantFault(const SoakOptions& o, const SegmentPlan& plan, engine::Runtime& rt) {
    static std::vector<std::unique_ptr<char[]>> leaked;
    const int f = rt.frameIndex();
    if (o.plant == "leak") {  // 256 KiB a frame, touched, never freed
        leaked.emplace_back(new char[256 << 10]);
        std::memset(leaked.back().get(), 1, 256 << 10);
    } else if (o.plant == "nan" && plan.index == 0 && f == plan.frames / 2 && rt.flag()) {
        const_cast<engine::Runtime&>(rt).mutableFlag()->mutableState().x(1, 7) = std::nan("");
    } else if (o.plant == "hang" && plan.index == 0 && f == plan.frames / 2) {
        for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
    }
}

// The live run; the hashes of its frames.
std::vector<std::uint64_t> runLive(const SegmentPlan& plan, const engine::SceneConfig& scene, SoakState& state,
                                   SegmentResult& result) {
    std::vector<std::uint64_t> hashes;
    hashes.reserve(std::size_t(plan.frames));
    FrameTimes& times = state.frameTimes[scene.name];
    engine::RunOptions o = windowOptions(plan, state.options);
    o.recordInput = plan.script;
    state.watchdog.beat(where(plan, "starting the scene"));
    engine::Runtime rt(scene, o);
    state.user.restart();
    for (;;) {
        state.watchdog.beat(where(plan, "frame " + std::to_string(rt.frameIndex()) + ", last gesture: " +
                                            state.user.gesture()));
        state.user.act(rt);
        const auto t0 = Clock::now();
        if (!rt.frame()) break;
        times.add(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        plantFault(state.options, plan, rt);
        hashes.push_back(hashPixels(rt.pixels()));
        if (std::string bad = nonFinite(rt); !bad.empty()) {
            result.problem = where(plan, "frame " + std::to_string(rt.frameIndex() - 1) + ": " + bad);
            break;
        }
        state.sampleMemory();
    }
    result.frames = int(hashes.size());
    result.refusals = rt.refusals();
    if (const engine::Flag* flag = rt.flag()) result.flagFailures = flag->failures(), result.firstFlagFailure = flag->firstFailure();
    if (rt.finish() != 0 && result.problem.empty()) result.problem = where(plan, "the run ended in an error");
    if (result.problem.empty() && result.frames != plan.frames && !engine::stopRequested())
        result.problem = where(plan, "stopped after " + std::to_string(result.frames) + " of " +
                                         std::to_string(plan.frames) + " frames");
    return hashes;
}

// The recorded input in a window with no user: the same frames, or where they part.
std::string replayDiffers(const SegmentPlan& plan, const engine::SceneConfig& scene, SoakState& state,
                          const std::vector<std::uint64_t>& live) {
    engine::RunOptions o = windowOptions(plan, state.options);
    o.scriptPath = plan.script;
    state.watchdog.beat(where(plan, "starting the replay"));
    engine::Runtime rt(scene, o);
    std::size_t f = 0;
    for (;; ++f) {
        state.watchdog.beat(where(plan, "replay frame " + std::to_string(f)));
        if (!rt.frame()) break;
        state.sampleMemory();
        if (f >= live.size() || hashPixels(rt.pixels()) != live[f])
            return where(plan, "the replay of " + plan.script + " differs from the live run at frame " + std::to_string(f));
    }
    if (rt.finish() != 0) return where(plan, "the replay ended in an error");
    if (f != live.size() && !engine::stopRequested())
        return where(plan, "the replay ran " + std::to_string(f) + " frames, the live run " + std::to_string(live.size()));
    return {};
}

}  // namespace

SegmentResult runSegment(const SegmentPlan& plan, SoakState& state) {
    SegmentResult result;
    const auto t0 = Clock::now();
    try {
        const engine::SceneConfig scene = engine::loadScene(plan.scene);
        const std::vector<std::uint64_t> live = runLive(plan, scene, state, result);
        SDL_FlushEvents(SDL_FIRSTEVENT, SDL_LASTEVENT);  // the user's last events were for the live window
        state.user.restart();
        if (state.options.replay && result.problem.empty() && !engine::stopRequested()) {
            result.problem = replayDiffers(plan, scene, state, live);
            result.replayed = true;
        }
    } catch (const engine::ConfigError& e) {
        result.problem = where(plan, std::string("error: ") + e.what());
    }
    result.wallSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return result;
}

}  // namespace soak
