#pragma once
// What the runtime renders and records: the GL context (OSMesa, or an SDL2 window), the
// renderer with the scene's meshes, the chase camera, and the frame writers.

#include <memory>
#include <string>
#include <vector>

#include "engine/flag.h"
#include "engine/input_script.h"
#include "engine/profiler.h"
#include "engine/runtime.h"
#include "engine/scene.h"

namespace engine {

class VehicleSystem;

class SceneView {
public:
    // Throws ConfigError when a context, model or writer cannot be created.
    SceneView(const SceneConfig& scene, const RunOptions& options, const VehicleSystem* vehicle,
              const Flag* flag, int frames);
    ~SceneView();
    static int contextsCreated();  // GL contexts ever constructed in this process

    bool hasWindow() const;
    bool windowClosed() const;
    Actions pollActions();  // keyboard and gamepad (window); also keeps the window alive

    // Draws the frame, reads it back, and hands it to the writers (each timed in its phase).
    void renderFrame(int frame, Profiler& profiler, int phRender, int phReadback, int phWrite);
    const std::vector<std::uint8_t>& pixels() const;

    // Drains the writers; false with *error when any write failed.
    bool finishRecording(int* framesWritten, std::string* video, std::string* error);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace engine
