#include "render/frame_upload.h"

namespace engine {

FrameUpload::~FrameUpload() { release(); }

void FrameUpload::release() {
    if (!gl_) return;
    if (fbo_) gl_->DeleteFramebuffers(1, &fbo_);
    if (texture_) gl_->DeleteTextures(1, &texture_);
    fbo_ = texture_ = 0;
}

void FrameUpload::show(const gl::Api& gl, const std::vector<std::uint8_t>& rgba, int width, int height) {
    if (rgba.size() != std::size_t(width) * height * 4) return;
    if (!texture_ || width != width_ || height != height_) {
        release();
        gl_ = &gl, width_ = width, height_ = height;
        gl.GenTextures(1, &texture_);
        gl.BindTexture(GL_TEXTURE_2D, texture_);
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl.GenFramebuffers(1, &fbo_);
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
        gl.FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
    }
    gl.BindTexture(GL_TEXTURE_2D, texture_);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl.BlitFramebuffer(0, 0, width, height, 0, height, width, 0, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace engine
