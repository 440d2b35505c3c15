#define FLAGSIM_IMGUI_GL_NO_NAMES
#include "ui/imgui_gl.h"

#define FLAGSIM_IMGUI_GL_DEFINE(type, name) type flagsim_imgui_##name = nullptr;
FLAGSIM_IMGUI_GL_FUNCTIONS(FLAGSIM_IMGUI_GL_DEFINE)
#undef FLAGSIM_IMGUI_GL_DEFINE

namespace engine::ui {

bool loadImguiGl(void* (*getProc)(const char*), const char** missing) {
#define FLAGSIM_IMGUI_GL_LOAD(type, name)                                   \
    flagsim_imgui_##name = reinterpret_cast<type>(getProc(#name));          \
    if (!flagsim_imgui_##name) {                                            \
        if (missing) *missing = #name;                                      \
        return false;                                                       \
    }
    FLAGSIM_IMGUI_GL_FUNCTIONS(FLAGSIM_IMGUI_GL_LOAD)
#undef FLAGSIM_IMGUI_GL_LOAD
    return true;
}

}  // namespace engine::ui
