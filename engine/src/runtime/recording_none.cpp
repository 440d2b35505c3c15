// Recording in a build without OSMesa and SDL2 (no frames to record): a clear error.

#include "engine/scene/config_error.h"
#include "runtime/recording.h"

namespace engine {

struct Recording::Impl {};

Recording::Recording(const SceneConfig& scene, const RunOptions&) {
    throw ConfigError(scene.file + ": subsystems: scene '" + scene.name +
                      "' needs 'recording', but this build has neither OSMesa nor SDL2 to render frames");
}
Recording::~Recording() = default;
void Recording::write(int, const std::vector<std::uint8_t>&) {}
bool Recording::finish(int*, std::string*, std::string*) { return true; }

}  // namespace engine
