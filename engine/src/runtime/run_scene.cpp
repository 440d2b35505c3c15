// The command-line driver: SIGINT and SIGTERM end the run after the current frame, a progress
// bar, the printed summary, and the next run when the panel switches scene or restarts.

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>

#include "engine/runtime.h"

namespace engine {

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> gStop{false};

void onStopSignal(int) { gStop = true; }

void drawProgress(int done, int total, double wallSeconds) {
    const int width = 30;
    const int filled = total > 0 ? done * width / total : width;
    std::fprintf(stderr, "\r[%.*s%*s] %d/%d frames  %.1f frames/s ", filled,
                 "##############################", width - filled, "", done, total,
                 wallSeconds > 0 ? done / wallSeconds : 0.0);
    std::fflush(stderr);
}

// One run of one scene; *next is the scene the panel asked for (empty: none).
int runOnce(const SceneConfig& scene, const RunOptions& options, std::string* next) {
    Runtime rt(scene, options);
    const bool progress = !options.noProgress && isatty(fileno(stderr));
    const auto t0 = Clock::now();
    while (rt.frame())
        if (progress && (rt.frameIndex() % 10 == 0 || rt.frameIndex() == rt.frameCount()))
            drawProgress(rt.frameIndex(), rt.frameCount(),
                         std::chrono::duration<double>(Clock::now() - t0).count());
    if (progress) std::fprintf(stderr, "\n");
    int code = rt.finish();
    *next = rt.nextScene();
    std::printf("scene %s: %d frames, %.2f s simulated, %.2f s wall\n", scene.name.c_str(),
                rt.frameIndex(), rt.simTime(), std::chrono::duration<double>(Clock::now() - t0).count());
    if (rt.flag()) {
        std::printf("cloth: %lld steps, solver %s, max pin error %.3g m, %d failed steps\n",
                    rt.flag()->steps(), cloth::describe(scene.flag.solver).c_str(), rt.maxPinError(),
                    rt.flag()->failures());
        if (rt.flag()->failures())
            std::printf("cloth: first failure: %s\n", rt.flag()->firstFailure().c_str());
    }
    std::printf("%s", rt.profiler().summaryTable().c_str());
    if (!options.outDir.empty()) std::printf("recorded to %s\n", options.outDir.c_str());
    return code;
}

}  // namespace

void installStopHandlers() {
    std::signal(SIGINT, onStopSignal);
    std::signal(SIGTERM, onStopSignal);
}
bool stopRequested() { return gStop.load(); }

int runScene(const SceneConfig& scene, const RunOptions& options) {
    installStopHandlers();
    std::string next;
    int code = runOnce(scene, options, &next);
    while (code == 0 && !next.empty() && !stopRequested()) {  // the panel switched scene or restarted
        SceneConfig chosen = loadScene(next);
        code = runOnce(chosen, options, &next);
    }
    if (stopRequested()) {
        std::printf("interrupted: outputs are complete up to the last frame\n");
        if (code == 0) code = 130;  // the shell's convention for a run ended by SIGINT
    }
    return code;
}

}  // namespace engine
