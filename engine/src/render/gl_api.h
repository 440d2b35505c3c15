#pragma once
// The OpenGL 3.3 core functions the renderer uses, loaded through the context's proc-address
// function (OSMesaGetProcAddress or SDL_GL_GetProcAddress). Nothing links libGL: linking it next
// to OSMesa silently renders nothing (PLATFORM.md).

#include <GL/glcorearb.h>

#include <string>

namespace engine::gl {

#define FLAGSIM_GL_FUNCTIONS(X)                                                              \
    X(PFNGLGETSTRINGPROC, GetString) X(PFNGLGETERRORPROC, GetError)                         \
    X(PFNGLCLEARPROC, Clear) X(PFNGLCLEARCOLORPROC, ClearColor) X(PFNGLENABLEPROC, Enable)  \
    X(PFNGLDISABLEPROC, Disable) X(PFNGLVIEWPORTPROC, Viewport) X(PFNGLCULLFACEPROC, CullFace) \
    X(PFNGLDEPTHFUNCPROC, DepthFunc) X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays) X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray) \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays) X(PFNGLGENBUFFERSPROC, GenBuffers)   \
    X(PFNGLBINDBUFFERPROC, BindBuffer) X(PFNGLBUFFERDATAPROC, BufferData)                   \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData) X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)       \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                    \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                            \
    X(PFNGLDRAWELEMENTSPROC, DrawElements) X(PFNGLDRAWARRAYSPROC, DrawArrays)               \
    X(PFNGLCREATESHADERPROC, CreateShader) X(PFNGLSHADERSOURCEPROC, ShaderSource)           \
    X(PFNGLCOMPILESHADERPROC, CompileShader) X(PFNGLGETSHADERIVPROC, GetShaderiv)           \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog) X(PFNGLCREATEPROGRAMPROC, CreateProgram) \
    X(PFNGLATTACHSHADERPROC, AttachShader) X(PFNGLLINKPROGRAMPROC, LinkProgram)             \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv) X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog) \
    X(PFNGLDELETESHADERPROC, DeleteShader) X(PFNGLDELETEPROGRAMPROC, DeleteProgram)         \
    X(PFNGLUSEPROGRAMPROC, UseProgram) X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)   \
    X(PFNGLUNIFORM1IPROC, Uniform1i) X(PFNGLUNIFORM1FPROC, Uniform1f)                       \
    X(PFNGLUNIFORM2FPROC, Uniform2f)                                                        \
    X(PFNGLUNIFORM3FVPROC, Uniform3fv) X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)       \
    X(PFNGLGENTEXTURESPROC, GenTextures) X(PFNGLBINDTEXTUREPROC, BindTexture)               \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D) X(PFNGLTEXPARAMETERIPROC, TexParameteri)             \
    X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                                                \
    X(PFNGLGENERATEMIPMAPPROC, GenerateMipmap) X(PFNGLACTIVETEXTUREPROC, ActiveTexture)     \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures) X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers) \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                            \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                                  \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                              \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers) X(PFNGLDRAWBUFFERPROC, DrawBuffer)   \
    X(PFNGLREADBUFFERPROC, ReadBuffer) X(PFNGLREADPIXELSPROC, ReadPixels)                   \
    X(PFNGLFINISHPROC, Finish) X(PFNGLPIXELSTOREIPROC, PixelStorei)                         \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers) X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer) \
    X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, RenderbufferStorageMultisample)               \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                            \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers) X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer) \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)

struct Api {
#define FLAGSIM_GL_DECLARE(type, name) type name = nullptr;
    FLAGSIM_GL_FUNCTIONS(FLAGSIM_GL_DECLARE)
#undef FLAGSIM_GL_DECLARE
};

using GetProc = void* (*)(const char*);

// Loads every function; false with *error naming the first one missing.
bool load(Api& api, GetProc getProc, std::string* error);

// A program of a vertex and a fragment shader. Throws std::runtime_error with the compiler's or
// the linker's log when either fails.
GLuint linkProgram(const Api& gl, const char* vertexSource, const char* fragmentSource);

}  // namespace engine::gl
