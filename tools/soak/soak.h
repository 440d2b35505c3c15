#pragma once
// The soak: the live demo in a window for a long time under a random user (random_user.h), run
// as segments (a scene, a few hundred to a few thousand frames, its input recorded); each
// segment's recorded input is replayed in a window and must give the same frames, bit for bit.
// It fails on a non-finite flag or vehicle, a run that ends in an error, a replay that differs,
// resident memory between segments (when their runtimes are gone) more than 5% above the
// warm-up's (the first minute, and every scene run once); a frame that never ends stops it with exit code 3
// (watch.h). Refused commands and the flag's caught failures are counted, not
// failures: they are the engine answering bad input as it should.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "random_user.h"
#include "watch.h"

namespace soak {

struct SoakOptions {
    double minutes = 2;         // segments start until this much wall time has passed
    std::uint64_t seed = 1;
    std::string outDir = "out/soak";
    bool replay = true;
    std::string plant;          // leak | nan | hang: a fault the watchers must catch (their test)
    int segmentFrames = 600;    // a segment runs a sixth of this to this many frames
    double warmupMinutes = 1;   // the warm-up: this long, and every scene run once
    double hangSeconds = 120;   // a frame (or a scene's start) longer than this is a hang
    std::vector<std::string> scenes;  // names in the assets; empty: every scene with a window
    int width = 0, height = 0;  // 0: the scene's
    std::string assetsDir;
};

// One segment: where it is in the soak and what it runs.
struct SegmentPlan {
    int index = 0;
    std::string scene;   // file
    int frames = 0;
    std::string script;  // the recorded input
};

// What one segment found.
struct SegmentResult {
    int frames = 0, refusals = 0, flagFailures = 0;
    std::string firstFlagFailure;
    std::string problem;  // empty: none
    bool replayed = false;
    double wallSeconds = 0;
};

// The soak's running state: the user, the watchdog, the memory and frame-time records.
struct SoakState {
    SoakState(const SoakOptions& o, VirtualPad& pad) : options(o), user(o.seed, pad), watchdog(o.hangSeconds) {}
    const SoakOptions& options;
    RandomUser user;
    Watchdog watchdog;
    std::map<std::string, FrameTimes> frameTimes;  // by scene name
    std::vector<std::pair<double, long>> memory;   // (minutes, resident KiB), about once a second
    std::vector<std::pair<double, long>> floors;   // (minutes, resident KiB) after each segment's end
    double warmedUp = -1;                          // the minute the warm-up ended (-1: not yet)
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    double minutes() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 60;
    }
    // The resident memory, when a second has passed since the last sample (`now`: at once).
    void sampleMemory(bool now = false) {
        const double m = minutes();
        if (now || memory.empty() || m - memory.back().first >= 1.0 / 60) memory.emplace_back(m, residentKiB());
    }
};

// The live segment under the random user, then (options.replay) its replay (segment.cpp).
SegmentResult runSegment(const SegmentPlan& plan, SoakState& state);

// Runs the soak, prints its report and writes outDir/soak.json. Returns the exit code: 0 when
// every watcher passed, 1 otherwise.
int runSoak(const SoakOptions& options);

}  // namespace soak
