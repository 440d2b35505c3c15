#include "render/gl_api.h"

#include <stdexcept>

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

namespace {

GLuint compile(const Api& gl, GLenum type, const char* source) {
    const GLuint s = gl.CreateShader(type);
    gl.ShaderSource(s, 1, &source, nullptr);
    gl.CompileShader(s);
    GLint ok = 0;
    gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        gl.GetShaderInfoLog(s, sizeof log, nullptr, log);
        gl.DeleteShader(s);
        throw std::runtime_error(std::string("shader does not compile: ") + log);
    }
    return s;
}

}  // namespace

GLuint linkProgram(const Api& gl, const char* vertexSource, const char* fragmentSource) {
    const GLuint v = compile(gl, GL_VERTEX_SHADER, vertexSource), f = compile(gl, GL_FRAGMENT_SHADER, fragmentSource);
    const GLuint p = gl.CreateProgram();
    gl.AttachShader(p, v);
    gl.AttachShader(p, f);
    gl.LinkProgram(p);
    gl.DeleteShader(v);
    gl.DeleteShader(f);
    GLint ok = 0;
    gl.GetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048];
        gl.GetProgramInfoLog(p, sizeof log, nullptr, log);
        gl.DeleteProgram(p);
        throw std::runtime_error(std::string("shader program does not link: ") + log);
    }
    return p;
}

}  // namespace engine::gl
