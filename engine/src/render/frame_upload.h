#pragma once
// A frame made on the CPU put back on screen: the post pass (frame_aa.h) works on the pixels read
// back, so in a window its result is uploaded into a texture and blitted (flipped: the pixels run
// top-down, GL's rows bottom-up) over framebuffer 0, where the panel then draws.

#include <cstdint>
#include <vector>

#include "render/gl_api.h"

namespace engine {

class FrameUpload {
public:
    FrameUpload() = default;
    ~FrameUpload();
    FrameUpload(const FrameUpload&) = delete;
    FrameUpload& operator=(const FrameUpload&) = delete;

    // RGBA8, rows top-down, width x height; the texture is made (or remade) at that size.
    void show(const gl::Api& gl, const std::vector<std::uint8_t>& rgba, int width, int height);

private:
    void release();
    const gl::Api* gl_ = nullptr;
    GLuint texture_ = 0, fbo_ = 0;
    int width_ = 0, height_ = 0;
};

}  // namespace engine
