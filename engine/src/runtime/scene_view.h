#pragma once
// What the runtime renders: the GL context (OSMesa, or an SDL2 window), the renderer with the
// scene's meshes, the chase camera. Each frame's pixels are read back for the recording (see
// recording.h), for --readback, and always offscreen.

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
    // Throws ConfigError when a context or model cannot be created.
    SceneView(const SceneConfig& scene, const RunOptions& options, const VehicleSystem* vehicle,
              const Flag* flag);
    ~SceneView();
    static int contextsCreated();  // GL contexts ever constructed in this process

    bool hasWindow() const;
    bool windowClosed() const;
    Actions pollActions();  // keyboard and gamepad (window); also keeps the window alive

    // Draws the frame and reads it back into pixels() (each timed in its phase).
    void renderFrame(Profiler& profiler, int phRender, int phReadback);
    const std::vector<std::uint8_t>& pixels() const;  // RGBA, top-down

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace engine
