#include "render/gl_api.h"

namespace engine::gl {

bool load(Api& api, GetProc getProc, std::string* error) {
#define FLAGSIM_GL_LOAD(type, name)                                              \
    api.name = reinterpret_cast<type>(getProc("gl" #name));                      \
    if (!api.name) {                                                             \
        if (error) *error = "OpenGL function gl" #name " is not available";      \
        return false;                                                            \
    }
    FLAGSIM_GL_FUNCTIONS(FLAGSIM_GL_LOAD)
#undef FLAGSIM_GL_LOAD
    return true;
}

}  // namespace engine::gl
