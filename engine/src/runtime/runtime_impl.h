#pragma once
// The runtime's state: the subsystems a scene declares, the clock, the input, and the commands'
// state (pause, single step, a requested scene). runtime_build.cpp builds it, frame_loop.cpp runs
// it, commands.cpp applies the commands, outputs.cpp writes what a run leaves; run_scene.cpp is
// the command-line driver around it.

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/scene/command.h"
#include "runtime/crossing_watch.h"
#include "engine/flag/flag.h"
#include "engine/scene/input_script.h"
#include "engine/profile/profiler.h"
#include "engine/runtime.h"
#include "engine/clock/tick_clock.h"
#include "engine/profile/trace.h"
#include "runtime/mesh_export.h"
#include "runtime/recording.h"
#include "runtime/scene_view.h"
#include "runtime/vehicle_system.h"

namespace engine {

using Clock = std::chrono::steady_clock;

// A run that writes no profile keeps this many frames of it at least (a minute at 60 Hz).
inline constexpr std::size_t kLiveProfileRows = 3600;

struct Runtime::Impl {
    SceneConfig scene;
    RunOptions opt;
    std::unique_ptr<Trace> trace;  // --trace; outlives the profiler and the vehicle (its teardown has zones)
    Profiler profiler;

    std::optional<InputScript> script;  // the actions, and the events (commands) by frame
    std::optional<InputRecorder> recorder;
    Actions actions;

    std::unique_ptr<VehicleSystem> vehicle;  // kVehicle
    std::unique_ptr<Flag> flag;              // kCloth
    RigidFrame fixedCarrier;                 // the world, for a fixed pole
    PoleMount mount;                         // the pole in its carrier's frame
    std::vector<cloth::Collider> staticColliders;
    std::unique_ptr<SceneView> view;         // kRender (+ kWindow)
    std::unique_ptr<Recording> recording;    // kRender + kRecording
    std::unique_ptr<MeshExport> meshExport;  // --export-mesh (kCloth)

    int frame = 0, frames = 0;
    int simFrame = 0;           // frames that advanced the tick schedule (not paused)
    bool paused = false, stepPending = false, restartSchedule = false;
    std::vector<std::string> scenes;  // the assets' scenes, for the panel
    std::string nextScene;      // the panel asked for this scene (or, restart, this one)
    SolverCounts lastCounts;      // the flag's counts at the last frame's end
    long long lastSteps = 0;
    std::optional<TickClock> clock;  // set by planFrames
    Clock::time_point nextFrame = Clock::now();
    double maxPinError = 0;
    std::unique_ptr<CrossingWatch> crossings;  // kCollision: the flag's crossings after each frame's ticks (or every tick)
    std::string stopReason = "completed";
    int refusals = 0;           // commands refused so far (the panel's and the script's)
    std::string lastRefusal;    // the last one, and why (the panel shows it)
    Clock::time_point start = Clock::now();

    RigidFrame carrier() const { return vehicle ? vehicle->carrier() : fixedCarrier; }
    void tick();
    // Commands (commands.cpp): the script's events and the panel's requests for this frame,
    // applied and recorded, and what the panel shows.
    void applyCommands();
    void apply(const Command& command);
    void refuse(const std::string& why);
    PanelState panelState() const;
    // The frame loop (frame_loop.cpp).
    std::string stopBefore() const;
    void readInput();
    void stepPhysics();
    void renderAndRecord();
    void exportMesh();
    void endFrame();
    void pace();
    long long ticksThisFrame();
    void stepFlag(double h);
    void measurePinError();
    void countCrossings();

    // Construction, in this order (runtime_build.cpp).
    void applyOptions();
    void planFrames();
    void enablePhases();
    void buildVehicle();
    void buildFlag();
    void buildView();
    void buildRecording();
};

// The names of the scene files in assetsDir/scenes, sorted.
std::vector<std::string> sceneNames(const std::string& assetsDir);

}  // namespace engine
