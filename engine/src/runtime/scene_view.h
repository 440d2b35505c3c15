#pragma once
// What the runtime renders: the GL context (OSMesa, or an SDL2 window), the renderer with the
// scene's meshes, the chase camera. Each frame's pixels are read back for the recording (see
// recording.h), for --readback, and always offscreen.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/flag/flag.h"
#include "engine/scene/input_script.h"
#include "engine/profile/profiler.h"
#include "engine/runtime.h"
#include "engine/scene/scene.h"
#include "ui/panel_types.h"

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
    // Keyboard and gamepad (window); also keeps the window alive. Events the panel takes go to
    // it; a drag or the wheel outside the panel orbits the camera.
    Actions pollActions();
    bool hasPanel() const;
    // The anti-aliasing that runs ("post", "msaa 4", "off") and why ("auto on llvmpipe").
    std::string antiAliasing() const;

    // Draws the frame and reads it back into pixels() (each timed in its phase). With a panel,
    // `panel` is what it shows: drawn after the readback in a window (the recorded frames stay the
    // scene's; Phase::Panel), before it with --overlay (Phase::Overlay).
    void renderFrame(Profiler& profiler, const PanelState* panel = nullptr, double frameSeconds = 0);
    const std::vector<std::uint8_t>& pixels() const;  // RGBA, top-down

    // What the user asked for since the last call: the panel's commands and requests, and the
    // camera's orbit as a command.
    PanelRequests takeRequests();
    // The camera command's orbit (yaw and pitch in degrees, zoom a distance factor).
    void setOrbit(double yawDeg, double pitchDeg, double zoom);
    std::optional<std::array<float, 4>> widgetRect(const std::string& label) const;
    std::vector<std::string> widgetLabels() const;  // the panel's widgets in the last frame

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace engine
