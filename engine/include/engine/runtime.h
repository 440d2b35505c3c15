#pragma once
// The engine runtime: builds only the subsystems a scene declares, runs the frame loop, and
// writes what was asked for (frames, video, the flag's meshes, profile, summary).
//
// One frame, in order (a phase exists only when its subsystem does):
//   input        actions from the script or the window (vehicle scenes)
//   physics      fixed ticks at physics_hz; each tick steps Bullet ("bullet"), then the flag:
//                air, cloth_forces, cloth_solve, collision
//   render       draw calls, readback (glFinish + glReadPixels)
//   write        hand the frame to the PNG writer threads and the video encoder
//   export_mesh  the flag's mesh written as an OBJ file (--export-mesh)
// Simulated time advances exactly 1/fps per frame when headless or replaying, so the same scene
// and script give the same frames; in a live window an accumulator follows the wall clock,
// clamped to max_ticks_per_frame so a slow frame cannot spiral.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cloth/crossings.h"
#include "engine/flag/flag.h"
#include "engine/profile/profiler.h"
#include "engine/scene/scene.h"

namespace engine {

struct RunOptions {
    std::string scriptPath;   // overrides the scene's script
    std::string outDir;       // empty: record nothing
    int frames = 0;           // 0: from duration
    double duration = 0;      // 0: the scene's
    bool video = false;
    bool noFrames = false;
    bool window = false;
    bool force = false;
    bool noProgress = false;
    std::string recordInput;
    std::string tracePath;      // empty: no trace; else a Chrome Trace Event JSON of the run
    std::string exportMeshDir;  // empty: none; else the flag's mesh after every frame, DIR/flag_NNNNNN.obj
    bool overlay = false;       // the panel's graphs and stats drawn into the recorded frames
    bool crossingsEveryTick = false;  // count the flag's crossings after every tick, not once per frame
    int width = 0, height = 0;  // 0: the scene's
    std::string aa;             // empty: the scene's render.aa; else auto, off, msaa or post
    int msaa = -1;              // -1: the scene's; else the samples, and (without aa) msaa or off
    bool readback = false;      // read every frame back even in a window without recording
    std::string assetsDir = defaultAssetsDir();
};

// Process-wide counters of expensive subsystem objects ever created (tests use them to show a
// scene did not build what it does not declare).
struct SubsystemCounters {
    int bulletWorlds = 0;
    int glContexts = 0;
    int windows = 0;
    int frameWriters = 0;
};
SubsystemCounters subsystemCounters();

class Runtime {
public:
    // Throws ConfigError for anything wrong with the scene, options, files or this build.
    Runtime(const SceneConfig& scene, const RunOptions& options);
    ~Runtime();
    Runtime(const Runtime&) = delete;
    Runtime& operator=(const Runtime&) = delete;

    // Runs one frame. False when the run is over (frame count reached, window closed, SIGINT).
    bool frame();
    // Flushes writers, writes profile.csv and summary.json, the recorded input, the trace.
    // Returns the process exit code (0, or 1 when a writer failed).
    int finish();

    int frameIndex() const;
    const SceneConfig& scene() const;  // as the commands so far left it
    // The scene file the panel asked to run next (switch or restart); empty otherwise. The run
    // stops at the frame after the request; runScene then starts that scene.
    const std::string& nextScene() const;
    // Where the panel last drew the widget with this label (tests click there); none without one.
    std::optional<std::array<float, 4>> widgetRect(const std::string& label) const;
    // The labels of the widgets the panel drew in the last frame (none without a panel).
    std::vector<std::string> widgetLabels() const;
    // The commands refused so far (the panel's and the script's; each told on stderr).
    int refusals() const;
    int frameCount() const;
    double simTime() const;
    const Profiler& profiler() const;
    const Flag* flag() const;                        // null without the cloth subsystem
    Flag* mutableFlag();
    const std::vector<std::uint8_t>& pixels() const; // last rendered frame (RGBA, top-down)
    double maxPinError() const;                      // over every tick so far
    // The most of each kind of the flag's crossings (cloth/crossings.h) in one count so far (after
    // each frame's ticks, or every tick); none without the collision subsystem.
    cloth::CrossingCounts mostCrossings() const;
    Eigen::Vector3d poleTop() const;                 // world space
    Eigen::Vector3d carrierVelocity() const;         // world space

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Runs a scene to the end with a progress bar and prints the profile summary.
int runScene(const SceneConfig& scene, const RunOptions& options);

// Set by SIGINT/SIGTERM; the frame loop finishes the current frame and stops.
void installStopHandlers();
bool stopRequested();

}  // namespace engine
