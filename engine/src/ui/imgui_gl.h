#pragma once
// The OpenGL functions Dear ImGui's OpenGL 3 backend calls, loaded through our context's
// proc-address function instead of the backend's own loader (which opens libGL and would draw
// nothing into an OSMesa buffer). The backend's source is compiled with this header forced in
// and IMGUI_IMPL_OPENGL_LOADER_CUSTOM, so its gl* calls are these pointers.

#include <GL/glcorearb.h>

#define FLAGSIM_IMGUI_GL_FUNCTIONS(X)                                                                   \
    X(PFNGLACTIVETEXTUREPROC, glActiveTexture) X(PFNGLATTACHSHADERPROC, glAttachShader)                 \
    X(PFNGLBINDBUFFERPROC, glBindBuffer) X(PFNGLBINDSAMPLERPROC, glBindSampler)                         \
    X(PFNGLBINDTEXTUREPROC, glBindTexture) X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)               \
    X(PFNGLBLENDEQUATIONPROC, glBlendEquation) X(PFNGLBLENDEQUATIONSEPARATEPROC, glBlendEquationSeparate) \
    X(PFNGLBLENDFUNCSEPARATEPROC, glBlendFuncSeparate) X(PFNGLBUFFERDATAPROC, glBufferData)             \
    X(PFNGLBUFFERSUBDATAPROC, glBufferSubData) X(PFNGLCOMPILESHADERPROC, glCompileShader)               \
    X(PFNGLCREATEPROGRAMPROC, glCreateProgram) X(PFNGLCREATESHADERPROC, glCreateShader)                 \
    X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers) X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)               \
    X(PFNGLDELETESHADERPROC, glDeleteShader) X(PFNGLDELETETEXTURESPROC, glDeleteTextures)               \
    X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays) X(PFNGLDETACHSHADERPROC, glDetachShader)       \
    X(PFNGLDISABLEPROC, glDisable) X(PFNGLDRAWELEMENTSPROC, glDrawElements)                             \
    X(PFNGLDRAWELEMENTSBASEVERTEXPROC, glDrawElementsBaseVertex) X(PFNGLENABLEPROC, glEnable)           \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray) X(PFNGLGENBUFFERSPROC, glGenBuffers) \
    X(PFNGLGENTEXTURESPROC, glGenTextures) X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)               \
    X(PFNGLGETATTRIBLOCATIONPROC, glGetAttribLocation) X(PFNGLGETINTEGERVPROC, glGetIntegerv)           \
    X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog) X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)         \
    X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog) X(PFNGLGETSHADERIVPROC, glGetShaderiv)             \
    X(PFNGLGETSTRINGPROC, glGetString) X(PFNGLGETSTRINGIPROC, glGetStringi)                             \
    X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation) X(PFNGLISENABLEDPROC, glIsEnabled)             \
    X(PFNGLLINKPROGRAMPROC, glLinkProgram) X(PFNGLPIXELSTOREIPROC, glPixelStorei)                       \
    X(PFNGLPOLYGONMODEPROC, glPolygonMode) X(PFNGLSCISSORPROC, glScissor)                               \
    X(PFNGLSHADERSOURCEPROC, glShaderSource) X(PFNGLTEXIMAGE2DPROC, glTexImage2D)                       \
    X(PFNGLTEXPARAMETERIPROC, glTexParameteri) X(PFNGLUNIFORM1IPROC, glUniform1i)                       \
    X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv) X(PFNGLUSEPROGRAMPROC, glUseProgram)               \
    X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer) X(PFNGLVIEWPORTPROC, glViewport)

#define FLAGSIM_IMGUI_GL_DECLARE(type, name) extern type flagsim_imgui_##name;
FLAGSIM_IMGUI_GL_FUNCTIONS(FLAGSIM_IMGUI_GL_DECLARE)
#undef FLAGSIM_IMGUI_GL_DECLARE

#ifndef FLAGSIM_IMGUI_GL_NO_NAMES  // the backend's gl* names are the pointers
#define glActiveTexture flagsim_imgui_glActiveTexture
#define glAttachShader flagsim_imgui_glAttachShader
#define glBindBuffer flagsim_imgui_glBindBuffer
#define glBindSampler flagsim_imgui_glBindSampler
#define glBindTexture flagsim_imgui_glBindTexture
#define glBindVertexArray flagsim_imgui_glBindVertexArray
#define glBlendEquation flagsim_imgui_glBlendEquation
#define glBlendEquationSeparate flagsim_imgui_glBlendEquationSeparate
#define glBlendFuncSeparate flagsim_imgui_glBlendFuncSeparate
#define glBufferData flagsim_imgui_glBufferData
#define glBufferSubData flagsim_imgui_glBufferSubData
#define glCompileShader flagsim_imgui_glCompileShader
#define glCreateProgram flagsim_imgui_glCreateProgram
#define glCreateShader flagsim_imgui_glCreateShader
#define glDeleteBuffers flagsim_imgui_glDeleteBuffers
#define glDeleteProgram flagsim_imgui_glDeleteProgram
#define glDeleteShader flagsim_imgui_glDeleteShader
#define glDeleteTextures flagsim_imgui_glDeleteTextures
#define glDeleteVertexArrays flagsim_imgui_glDeleteVertexArrays
#define glDetachShader flagsim_imgui_glDetachShader
#define glDisable flagsim_imgui_glDisable
#define glDrawElements flagsim_imgui_glDrawElements
#define glDrawElementsBaseVertex flagsim_imgui_glDrawElementsBaseVertex
#define glEnable flagsim_imgui_glEnable
#define glEnableVertexAttribArray flagsim_imgui_glEnableVertexAttribArray
#define glGenBuffers flagsim_imgui_glGenBuffers
#define glGenTextures flagsim_imgui_glGenTextures
#define glGenVertexArrays flagsim_imgui_glGenVertexArrays
#define glGetAttribLocation flagsim_imgui_glGetAttribLocation
#define glGetIntegerv flagsim_imgui_glGetIntegerv
#define glGetProgramInfoLog flagsim_imgui_glGetProgramInfoLog
#define glGetProgramiv flagsim_imgui_glGetProgramiv
#define glGetShaderInfoLog flagsim_imgui_glGetShaderInfoLog
#define glGetShaderiv flagsim_imgui_glGetShaderiv
#define glGetString flagsim_imgui_glGetString
#define glGetStringi flagsim_imgui_glGetStringi
#define glGetUniformLocation flagsim_imgui_glGetUniformLocation
#define glIsEnabled flagsim_imgui_glIsEnabled
#define glLinkProgram flagsim_imgui_glLinkProgram
#define glPixelStorei flagsim_imgui_glPixelStorei
#define glPolygonMode flagsim_imgui_glPolygonMode
#define glScissor flagsim_imgui_glScissor
#define glShaderSource flagsim_imgui_glShaderSource
#define glTexImage2D flagsim_imgui_glTexImage2D
#define glTexParameteri flagsim_imgui_glTexParameteri
#define glUniform1i flagsim_imgui_glUniform1i
#define glUniformMatrix4fv flagsim_imgui_glUniformMatrix4fv
#define glUseProgram flagsim_imgui_glUseProgram
#define glVertexAttribPointer flagsim_imgui_glVertexAttribPointer
#define glViewport flagsim_imgui_glViewport
#endif

namespace engine::ui {
// Loads every pointer with the current context's getProc; false names the first one missing.
bool loadImguiGl(void* (*getProc)(const char*), const char** missing);
}  // namespace engine::ui
