#include "engine/render/gl_context.h"

#include <atomic>

namespace engine {

namespace {
std::atomic<int> gContexts{0};
}

GLContext::GLContext(int w, int h) : width_(w), height_(h) { ++gContexts; }
int GLContext::contextsCreated() { return gContexts.load(); }

#ifndef FLAGSIM_HAS_OSMESA
std::unique_ptr<GLContext> createOffscreenContext(int, int, std::string* error) {
    if (error) *error = "this build has no OSMesa (FLAGSIM_WITH_OSMESA=OFF): no headless rendering";
    return nullptr;
}
#endif
#ifndef FLAGSIM_HAS_SDL2
std::unique_ptr<GLContext> createWindowContext(int, int, const std::string&, std::string* error) {
    if (error) *error = "this build has no SDL2 (FLAGSIM_WITH_SDL2=OFF): no window";
    return nullptr;
}
#endif

}  // namespace engine
