#pragma once
// A gamepad the soak plugs in and pulls out: SDL's virtual joystick with a game controller's axes
// and buttons. The window finds it as it finds a real one (SDL_CONTROLLERDEVICEADDED) and loses it
// the same way (SDL_CONTROLLERDEVICEREMOVED).

#include <SDL.h>

namespace soak {

class VirtualPad {
public:
    VirtualPad() = default;
    ~VirtualPad() { unplug(); }
    VirtualPad(const VirtualPad&) = delete;
    VirtualPad& operator=(const VirtualPad&) = delete;

    bool plug();  // false, with SDL's reason on stderr, where SDL cannot make one
    void unplug();
    bool plugged() const { return joystick_ != nullptr; }
    void setAxis(SDL_GameControllerAxis axis, double value);  // -1..1 (a trigger: 0..1)
    void setButton(SDL_GameControllerButton button, bool down);

private:
    SDL_Joystick* joystick_ = nullptr;
};

}  // namespace soak
