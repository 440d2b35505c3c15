// An SDL2 window with an OpenGL 3.3 core context, and its keyboard and gamepad as actions.

#include <SDL.h>

#include <algorithm>
#include <array>

#include "engine/render/gl_context.h"

namespace engine {

namespace {

class SdlWindowContext final : public GLContext {
public:
    SdlWindowContext(int w, int h, SDL_Window* window, SDL_GLContext gl)
        : GLContext(w, h), window_(window), gl_(gl) {
        openPad();
    }
    ~SdlWindowContext() override {
        if (pad_) SDL_GameControllerClose(pad_);
        SDL_GL_DeleteContext(gl_);
        SDL_DestroyWindow(window_);
        SDL_QuitSubSystem(SDL_INIT_VIDEO | SDL_INIT_GAMECONTROLLER);
    }
    void* (*procAddress())(const char*) override { return &SDL_GL_GetProcAddress; }
    void present() override { SDL_GL_SwapWindow(window_); }
    bool makeCurrent() override { return SDL_GL_MakeCurrent(window_, gl_) == 0; }
    bool isWindow() const override { return true; }

    bool pollEvents(Actions& a, const EventSink& sink) override {
        SDL_Event e;
        bool open = true;
        while (SDL_PollEvent(&e)) {
            if (e.type == SDL_QUIT) open = false;
            const bool taken = sink && sink(&e);
            if (e.type == SDL_KEYUP) held_[e.key.keysym.scancode] = false;  // a release always counts
            if (taken) continue;
            if (e.type == SDL_KEYDOWN && e.key.keysym.sym == SDLK_ESCAPE) open = false;
            if (e.type == SDL_KEYDOWN) held_[e.key.keysym.scancode] = true;
            if (e.type == SDL_CONTROLLERDEVICEADDED && !pad_) pad_ = SDL_GameControllerOpen(e.cdevice.which);
            if (e.type == SDL_CONTROLLERDEVICEREMOVED && pad_ &&
                e.cdevice.which == SDL_JoystickInstanceID(SDL_GameControllerGetJoystick(pad_))) {
                SDL_GameControllerClose(pad_);  // pulled out: the next one plugged in, if any
                pad_ = nullptr;
                openPad();
            }
        }
        auto key = [this](SDL_Scancode x, SDL_Scancode y) { return (held_[x] || held_[y]) ? 1.0 : 0.0; };
        a.throttle = key(SDL_SCANCODE_UP, SDL_SCANCODE_W);
        a.brake = key(SDL_SCANCODE_DOWN, SDL_SCANCODE_S);
        a.steer = key(SDL_SCANCODE_LEFT, SDL_SCANCODE_A) - key(SDL_SCANCODE_RIGHT, SDL_SCANCODE_D);
        a.handbrake = held_[SDL_SCANCODE_SPACE] ? 1.0 : 0.0;
        if (pad_) {  // triggers: throttle and brake; left stick: steer; A: handbrake
            auto axis = [this](SDL_GameControllerAxis x) {
                return SDL_GameControllerGetAxis(pad_, x) / 32767.0;
            };
            const double stick = axis(SDL_CONTROLLER_AXIS_LEFTX);
            a.throttle = std::max(a.throttle, axis(SDL_CONTROLLER_AXIS_TRIGGERRIGHT));
            a.brake = std::max(a.brake, axis(SDL_CONTROLLER_AXIS_TRIGGERLEFT));
            if (std::abs(stick) > 0.1) a.steer = std::clamp(-stick, -1.0, 1.0);
            if (SDL_GameControllerGetButton(pad_, SDL_CONTROLLER_BUTTON_A)) a.handbrake = 1;
        }
        a.throttle = std::clamp(a.throttle, -1.0, 1.0);
        a.brake = std::clamp(a.brake, 0.0, 1.0);
        return open;
    }

private:
    void openPad() {
        for (int i = 0; i < SDL_NumJoysticks() && !pad_; ++i)
            if (SDL_IsGameController(i)) pad_ = SDL_GameControllerOpen(i);
    }

    SDL_Window* window_;
    SDL_GLContext gl_;
    SDL_GameController* pad_ = nullptr;
    std::array<bool, SDL_NUM_SCANCODES> held_{};  // keys down, from the events (a pushed event counts too)
};

}  // namespace

std::unique_ptr<GLContext> createWindowContext(int width, int height, const std::string& title,
                                               std::string* error) {
    if (SDL_InitSubSystem(SDL_INIT_VIDEO | SDL_INIT_GAMECONTROLLER) != 0) {
        if (error) *error = std::string("SDL could not start video: ") + SDL_GetError();
        return nullptr;
    }
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
    SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
    SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
    SDL_Window* window = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                          width, height, SDL_WINDOW_OPENGL | SDL_WINDOW_SHOWN);
    if (!window) {
        if (error) *error = std::string("SDL could not open a window: ") + SDL_GetError();
        SDL_QuitSubSystem(SDL_INIT_VIDEO | SDL_INIT_GAMECONTROLLER);
        return nullptr;
    }
    SDL_GLContext gl = SDL_GL_CreateContext(window);
    if (!gl) {
        if (error) *error = std::string("SDL could not create an OpenGL 3.3 context: ") + SDL_GetError();
        SDL_DestroyWindow(window);
        SDL_QuitSubSystem(SDL_INIT_VIDEO | SDL_INIT_GAMECONTROLLER);
        return nullptr;
    }
    SDL_GL_SetSwapInterval(0);  // the engine paces frames itself
    return std::make_unique<SdlWindowContext>(width, height, window, gl);
}

}  // namespace engine
