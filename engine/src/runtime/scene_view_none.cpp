// Rendering in a build without OSMesa and SDL2: a scene that declares it gets a clear error.

#include "engine/scene/config_error.h"
#include "runtime/scene_view.h"

namespace engine {

struct SceneView::Impl {};

SceneView::SceneView(const SceneConfig& scene, const RunOptions&, const VehicleSystem*, const Flag*) {
    throw ConfigError(scene.file + ": subsystems: scene '" + scene.name +
                      "' needs 'render', but this build has neither OSMesa nor SDL2");
}
SceneView::~SceneView() = default;
int SceneView::contextsCreated() { return 0; }
bool SceneView::hasWindow() const { return false; }
bool SceneView::windowClosed() const { return false; }
Actions SceneView::pollActions() { return {}; }
bool SceneView::hasPanel() const { return false; }
std::string SceneView::antiAliasing() const { return "off"; }
void SceneView::renderFrame(Profiler&, const PanelState*, double) {}
PanelRequests SceneView::takeRequests() { return {}; }
void SceneView::setOrbit(double, double, double) {}
std::optional<std::array<float, 4>> SceneView::widgetRect(const std::string&) const { return std::nullopt; }
std::vector<std::string> SceneView::widgetLabels() const { return {}; }
const std::vector<std::uint8_t>& SceneView::pixels() const {
    static const std::vector<std::uint8_t> none;
    return none;
}

}  // namespace engine
