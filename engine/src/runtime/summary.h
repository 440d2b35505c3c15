#pragma once
// summary.json: what ran, and the profile summary per phase.

#include <string>

#include "cloth/contact.h"
#include "runtime/crossing_watch.h"

#include "engine/profile/profiler.h"
#include "engine/scene/scene.h"

namespace engine {

struct RunFacts {
    std::string scene, solver, subsystems, script, stopReason, antiAliasing;
    int frames = 0, width = 0, height = 0;
    double simTime = 0, wallSeconds = 0, maxPinError = 0;
    long long clothSteps = 0;
    double iterationsMean = 0, linearIterationsMean = 0;  // the solver's, per cloth step
    int iterationsMax = 0;
    int clothFailures = 0;
    std::string firstClothFailure;
    int framesWritten = 0;
    std::string video;  // path, or empty
    std::string writerError;
    std::string meshDir;  // --export-mesh, or empty (then the summary has no "export_mesh")
    int meshesWritten = 0;
    std::string meshError;
    bool crossingsCounted = false;  // the flag's crossings (kCollision)
    bool crossingsEveryTick = false;  // counted after every tick, else after each frame's ticks
    CrossingTally crossings;
    bool contactOn = false;  // the flag's contact stage ran (then the summary has "contact")
    cloth::ContactReport contact;  // its work, summed over the run
};

// Writes to a temporary name and renames it into place. Returns false with *error set.
bool writeSummary(const std::string& path, const RunFacts& facts, const Profiler& profiler,
                  std::string* error);

}  // namespace engine
