// flagsim_soak: the live demo for a long time under a seeded random user (soak.h). Needs a
// display (xvfb-run on a machine without one).

#include <CLI/CLI.hpp>

#include <cstdio>

#include "engine/runtime.h"
#include "engine/scene/scene.h"
#include "soak.h"

int main(int argc, char** argv) {
    CLI::App app{"flagsim_soak: the live demo under a random user, watched (memory, finite state, hangs, "
                 "frame times) and each segment's recorded input replayed to the same frames."};
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    soak::SoakOptions o;
    o.assetsDir = engine::defaultAssetsDir();
    app.add_option("--minutes", o.minutes, "wall minutes: segments start until this much time has passed")
        ->check(CLI::Range(0.01, 10000.0))
        ->capture_default_str();
    app.add_option("--seed", o.seed, "the random user's seed (the same seed, the same soak on one build)")
        ->capture_default_str();
    app.add_option("--out", o.outDir, "folder for the recorded inputs (segment-NNN.json) and soak.json")
        ->capture_default_str();
    app.add_flag("!--no-replay", o.replay, "do not replay the segments (half the time; no determinism check)");
    app.add_option("--scenes", o.scenes, "scene names to draw from (default: every scene with a window)")
        ->delimiter(',');
    app.add_option("--segment-frames", o.segmentFrames, "a segment runs a sixth of this to this many frames")
        ->check(CLI::Range(6, 1000000))
        ->capture_default_str();
    app.add_option("--warmup-minutes", o.warmupMinutes, "memory is judged after this long (and every scene run once)")
        ->check(CLI::Range(0.0, 10000.0))
        ->capture_default_str();
    app.add_option("--hang-seconds", o.hangSeconds, "a frame longer than this is a hang (exit code 3)")
        ->check(CLI::Range(1.0, 86400.0))
        ->capture_default_str();
    app.add_option("--plant", o.plant, "a fault the watchers must catch: leak (memory), nan (the flag), hang")
        ->check(CLI::IsMember({"leak", "nan", "hang"}));
    app.add_option("--width", o.width, "window width (default: the scene's)")->check(CLI::Range(64, 7680));
    app.add_option("--height", o.height, "window height (default: the scene's)")->check(CLI::Range(64, 4320));
    app.add_option("--assets", o.assetsDir, "assets folder")->check(CLI::ExistingDirectory)->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    for (const std::string& s : o.scenes) {
        try {
            engine::loadScene(engine::resolveScenePath(s, o.assetsDir));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "flagsim_soak: --scenes %s: %s\n", s.c_str(), e.what());
            return 2;
        }
    }
    engine::installStopHandlers();
    return soak::runSoak(o);
}
