#pragma once
// Anti-aliasing by multisampling: the main pass draws into a multisampled framebuffer (color and
// depth renderbuffers), then resolves it into the context's framebuffer, where the readback and
// the panel find it. Both contexts offer it (llvmpipe, and OSMesa's buffer cannot itself be
// multisampled, which is why the pass has its own framebuffer).

#include <string>

#include "render/gl_api.h"

namespace engine {

class MsaaTarget {
public:
    MsaaTarget() = default;
    ~MsaaTarget();
    MsaaTarget(const MsaaTarget&) = delete;
    MsaaTarget& operator=(const MsaaTarget&) = delete;

    // `samples` clamped to what the context offers; false (and *why) when it offers none or the
    // framebuffer is incomplete, leaving nothing behind.
    bool create(const gl::Api& gl, int width, int height, int samples, std::string* why);
    void bind() const;     // the main pass draws here
    void resolve() const;  // into framebuffer 0, then binds it

private:
    void release();
    const gl::Api* gl_ = nullptr;
    GLuint fbo_ = 0, color_ = 0, depth_ = 0;
    int width_ = 0, height_ = 0, samples_ = 0;
};

}  // namespace engine
