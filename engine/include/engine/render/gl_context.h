#pragma once
// Where the renderer draws: an offscreen OSMesa buffer (headless) or an SDL2 window. Both give
// an OpenGL 3.3 core context and a proc-address function; the renderer is the same for both.

#include <functional>
#include <memory>
#include <string>

#include "engine/scene/input_script.h"

namespace engine {

class GLContext {
public:
    virtual ~GLContext() = default;
    virtual void* (*procAddress())(const char*) = 0;
    // Several contexts may live in one process (tests): each frame makes its own current.
    virtual bool makeCurrent() = 0;
    virtual void present() {}             // swap buffers (window)
    virtual bool isWindow() const { return false; }
    // Each window event (an SDL_Event) is offered to the sink first; true means the sink took it
    // (the panel), and it does not drive. The rest: keyboard and gamepad mapped to driving
    // actions, the keys held as their events said. False once the user closed the window (or
    // pressed Escape).
    using EventSink = std::function<bool(const void* event)>;
    virtual bool pollEvents(Actions& actions, const EventSink& sink) {
        (void)actions, (void)sink;
        return true;
    }
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
