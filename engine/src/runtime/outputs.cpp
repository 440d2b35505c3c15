// What a run leaves: the recording's writers drained, the meshes' first write error (each mesh was
// written as its frame ended), the recorded input, profile.csv, summary.json and the trace, each
// written to a temporary name and renamed.

#include <chrono>
#include <cstdio>

#include "runtime/runtime_impl.h"
#include "runtime/summary.h"

namespace engine {

int Runtime::finish() {
    Impl& m = *impl_;
    int code = 0;
    RunFacts f;
    f.scene = m.scene.name;
    f.subsystems = describeSubsystems(m.scene.subsystems);
    f.solver = (m.scene.subsystems & kCloth) ? cloth::describe(m.scene.flag.solver) : "";
    f.antiAliasing = m.view ? m.view->antiAliasing() : "";
    f.script = m.script ? (m.opt.scriptPath.empty() ? m.scene.script : m.opt.scriptPath) : "";
    f.frames = m.frame;
    f.width = m.scene.render.width;
    f.height = m.scene.render.height;
    f.simTime = m.clock->simTime();
    f.wallSeconds = std::chrono::duration<double>(Clock::now() - m.start).count();
    f.stopReason = m.stopReason;
    f.maxPinError = m.maxPinError;
    if (m.flag) {
        f.clothSteps = m.flag->steps();
        const SolverCounts& counts = m.flag->solverCounts();
        const double steps = double(std::max<long long>(f.clothSteps, 1));
        f.iterationsMean = double(counts.iterations) / steps;
        f.linearIterationsMean = double(counts.linearIterations) / steps;
        f.iterationsMax = counts.maxIterations;
        f.clothFailures = m.flag->failures();
        f.firstClothFailure = m.flag->firstFailure();
        f.contactOn = m.flag->contactOn(), f.contact = m.flag->contactTotal();
    }
    if (m.crossings) f.crossingsCounted = true, f.crossings = m.crossings->tally(), f.crossingsEveryTick = m.opt.crossingsEveryTick;
    if (m.recording) {
        std::string error;
        if (!m.recording->finish(&f.framesWritten, &f.video, &error)) {
            f.writerError = error;
            std::fprintf(stderr, "flagsim: error: %s\n", error.c_str());
            code = 1;
        }
    }
    if (m.meshExport) {
        f.meshDir = m.meshExport->dir();
        f.meshesWritten = m.meshExport->written();
        f.meshError = m.meshExport->error();
        if (!m.meshExport->ok()) {
            std::fprintf(stderr, "flagsim: error: %s\n", f.meshError.c_str());
            code = 1;
        }
    }
    if (m.recorder) {
        std::string error;
        if (!m.recorder->script().save(m.opt.recordInput, &error)) {
            std::fprintf(stderr, "flagsim: error: %s\n", error.c_str());
            code = 1;
        }
    }
    if (!m.opt.outDir.empty()) {
        std::string error;
        if (!m.profiler.writeCsv(m.opt.outDir + "/profile.csv", &error) ||
            !writeSummary(m.opt.outDir + "/summary.json", f, m.profiler, &error)) {
            std::fprintf(stderr, "flagsim: error: %s\n", error.c_str());
            code = 1;
        }
    }
    if (m.trace) {
        std::string error;
        if (!m.trace->write(m.opt.tracePath, &error)) {
            std::fprintf(stderr, "flagsim: error: --trace %s\n", error.c_str());
            code = 1;
        }
    }
    return code;
}

}  // namespace engine
