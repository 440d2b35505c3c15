#pragma once
// Where the renderer draws: an offscreen OSMesa buffer (headless) or an SDL2 window. Both give
// an OpenGL 3.3 core context and a proc-address function; the renderer is the same for both.

#include <memory>
#include <string>

#include "engine/input_script.h"

namespace engine {

class GLContext {
public:
    virtual ~GLContext() = default;
    virtual void* (*procAddress())(const char*) = 0;
    // Several contexts may live in one process (tests): each frame makes its own current.
    virtual bool makeCurrent() = 0;
    virtual void present() {}             // swap buffers (window)
    virtual bool isWindow() const { return false; }
    // Window events: keyboard and gamepad mapped to driving actions; false once the user closed
    // the window (or pressed Escape).
    virtual bool pollEvents(Actions& actions) { (void)actions; return true; }
    int width() const { return width_; }
    int height() const { return height_; }
    static int contextsCreated();  // process-wide count

protected:
    GLContext(int w, int h);
    int width_, height_;
};

// Each returns null and sets *error when the context cannot be made (or this build lacks it).
std::unique_ptr<GLContext> createOffscreenContext(int width, int height, std::string* error);
std::unique_ptr<GLContext> createWindowContext(int width, int height, const std::string& title,
                                               std::string* error);

}  // namespace engine
