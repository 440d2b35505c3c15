// Headless OpenGL through OSMesa (llvmpipe): a 3.3 core context drawing into our own buffer.

#include <GL/osmesa.h>

#include <vector>

#include "engine/render/gl_context.h"

namespace engine {

namespace {

class OsMesaContext final : public GLContext {
public:
    OsMesaContext(int w, int h, OSMesaContext ctx) : GLContext(w, h), ctx_(ctx), buffer_(size_t(w) * h * 4) {}
    ~OsMesaContext() override { OSMesaDestroyContext(ctx_); }
    bool makeCurrent() override {
        return OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, width_, height_);
    }
    void* (*procAddress())(const char*) override { return &getProc; }

private:
    static void* getProc(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }
    OSMesaContext ctx_;
    std::vector<unsigned char> buffer_;
};

}  // namespace

std::unique_ptr<GLContext> createOffscreenContext(int width, int height, std::string* error) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx) {
        if (error) *error = "OSMesa could not create an OpenGL 3.3 core context";
        return nullptr;
    }
    auto c = std::make_unique<OsMesaContext>(width, height, ctx);
    if (!c->makeCurrent()) {
        if (error) *error = "OSMesa could not make its context current";
        return nullptr;
    }
    return c;
}

}  // namespace engine
