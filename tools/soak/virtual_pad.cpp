#include "virtual_pad.h"

#include <algorithm>
#include <cstdio>

namespace soak {

bool VirtualPad::plug() {
    if (joystick_) return true;
    const int index = SDL_JoystickAttachVirtual(SDL_JOYSTICK_TYPE_GAMECONTROLLER, SDL_CONTROLLER_AXIS_MAX,
                                                SDL_CONTROLLER_BUTTON_MAX, 0);
    if (index < 0 || !(joystick_ = SDL_JoystickOpen(index))) {
        std::fprintf(stderr, "flagsim_soak: no virtual gamepad: %s\n", SDL_GetError());
        if (index >= 0) SDL_JoystickDetachVirtual(index);
        return false;
    }
    return true;
}

void VirtualPad::unplug() {
    if (!joystick_) return;
    const SDL_JoystickID id = SDL_JoystickInstanceID(joystick_);
    SDL_JoystickClose(joystick_);
    joystick_ = nullptr;
    for (int i = 0; i < SDL_NumJoysticks(); ++i)
        if (SDL_JoystickGetDeviceInstanceID(i) == id) SDL_JoystickDetachVirtual(i);
}

void VirtualPad::setAxis(SDL_GameControllerAxis axis, double value) {
    if (joystick_) SDL_JoystickSetVirtualAxis(joystick_, axis, Sint16(std::clamp(value, -1.0, 1.0) * 32767));
}

void VirtualPad::setButton(SDL_GameControllerButton button, bool down) {
    if (joystick_) SDL_JoystickSetVirtualButton(joystick_, button, down ? SDL_PRESSED : SDL_RELEASED);
}

}  // namespace soak
