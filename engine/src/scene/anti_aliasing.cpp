#include "engine/scene/anti_aliasing.h"

#include <string>

namespace engine {

const char* toString(AntiAliasing aa) {
    switch (aa) {
        case AntiAliasing::Auto: return "auto";
        case AntiAliasing::Off: return "off";
        case AntiAliasing::Msaa: return "msaa";
        case AntiAliasing::Post: return "post";
    }
    return "?";
}

bool antiAliasingOf(std::string_view word, AntiAliasing& out) {
    for (AntiAliasing aa : {AntiAliasing::Auto, AntiAliasing::Off, AntiAliasing::Msaa, AntiAliasing::Post})
        if (word == toString(aa)) return out = aa, true;
    return false;
}

}  // namespace engine
