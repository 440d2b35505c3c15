#include "render/msaa_target.h"

#include <algorithm>

namespace engine {

MsaaTarget::~MsaaTarget() { release(); }

void MsaaTarget::release() {
    if (!gl_) return;
    if (fbo_) gl_->DeleteFramebuffers(1, &fbo_);
    if (color_) gl_->DeleteRenderbuffers(1, &color_);
    if (depth_) gl_->DeleteRenderbuffers(1, &depth_);
    fbo_ = color_ = depth_ = 0;
}

bool MsaaTarget::create(const gl::Api& gl, int width, int height, int samples, std::string* why) {
    gl_ = &gl;
    GLint offered = 0;
    gl.GetIntegerv(GL_MAX_SAMPLES, &offered);
    samples_ = std::min(samples, int(offered));
    if (samples_ < 2) {
        if (why) *why = "the context offers no multisampling (GL_MAX_SAMPLES = " + std::to_string(offered) + ")";
        samples_ = 0;
        return false;
    }
    width_ = width, height_ = height;
    gl.GenRenderbuffers(1, &color_);
    gl.BindRenderbuffer(GL_RENDERBUFFER, color_);
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, width, height);
    gl.GenRenderbuffers(1, &depth_);
    gl.BindRenderbuffer(GL_RENDERBUFFER, depth_);
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH_COMPONENT24, width, height);
    gl.GenFramebuffers(1, &fbo_);
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    const bool complete = gl.CheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!complete) {
        if (why) *why = "the multisampled framebuffer is incomplete";
        release();
        samples_ = 0;
        return false;
    }
    return true;
}

void MsaaTarget::bind() const { gl_->BindFramebuffer(GL_FRAMEBUFFER, fbo_); }

void MsaaTarget::resolve() const {
    gl_->BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    gl_->BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl_->BlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl_->BindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace engine
