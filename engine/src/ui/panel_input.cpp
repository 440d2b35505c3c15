// SDL events into the panel. The events themselves are the input: Dear ImGui's SDL backend reads
// the mouse from SDL's global state, which an event pushed by a test (or a replay) does not move,
// so the panel follows the event stream instead, the same for a real mouse and a synthetic one.

#include <imgui.h>

#include "ui/panel.h"

#ifdef FLAGSIM_HAS_SDL2
#include <SDL.h>
#endif

namespace engine {

#ifdef FLAGSIM_HAS_SDL2
namespace {

void mapKeys(ImGuiIO& io) {
    const std::pair<ImGuiKey, SDL_Scancode> keys[] = {
        {ImGuiKey_Tab, SDL_SCANCODE_TAB},         {ImGuiKey_LeftArrow, SDL_SCANCODE_LEFT},
        {ImGuiKey_RightArrow, SDL_SCANCODE_RIGHT}, {ImGuiKey_UpArrow, SDL_SCANCODE_UP},
        {ImGuiKey_DownArrow, SDL_SCANCODE_DOWN},  {ImGuiKey_Home, SDL_SCANCODE_HOME},
        {ImGuiKey_End, SDL_SCANCODE_END},         {ImGuiKey_Delete, SDL_SCANCODE_DELETE},
        {ImGuiKey_Backspace, SDL_SCANCODE_BACKSPACE}, {ImGuiKey_Enter, SDL_SCANCODE_RETURN},
        {ImGuiKey_Escape, SDL_SCANCODE_ESCAPE},   {ImGuiKey_KeyPadEnter, SDL_SCANCODE_KP_ENTER},
        {ImGuiKey_A, SDL_SCANCODE_A},             {ImGuiKey_C, SDL_SCANCODE_C},
        {ImGuiKey_V, SDL_SCANCODE_V},             {ImGuiKey_X, SDL_SCANCODE_X},
    };
    for (const auto& [key, code] : keys) io.KeyMap[key] = code;
}

int buttonIndex(Uint8 button) {
    return button == SDL_BUTTON_LEFT ? 0 : button == SDL_BUTTON_RIGHT ? 1 : button == SDL_BUTTON_MIDDLE ? 2 : -1;
}

}  // namespace
#endif

bool Panel::handleEvent(const void* event) {
#ifdef FLAGSIM_HAS_SDL2
    if (!interactive_) return false;
    ImGui::SetCurrentContext(ctx_);
    ImGuiIO& io = ImGui::GetIO();
    if (io.KeyMap[ImGuiKey_Tab] < 0) mapKeys(io);
    const SDL_Event& e = *static_cast<const SDL_Event*>(event);
    switch (e.type) {
        case SDL_MOUSEMOTION:
            io.MousePos = ImVec2(float(e.motion.x), float(e.motion.y));
            return io.WantCaptureMouse;
        case SDL_MOUSEBUTTONDOWN:
        case SDL_MOUSEBUTTONUP: {
            io.MousePos = ImVec2(float(e.button.x), float(e.button.y));
            const int b = buttonIndex(e.button.button);
            if (b < 0) return io.WantCaptureMouse;
            mouse_.down[b] = e.type == SDL_MOUSEBUTTONDOWN;
            if (mouse_.down[b]) mouse_.pressed[b] = true;
            return io.WantCaptureMouse;
        }
        case SDL_MOUSEWHEEL:
            io.MouseWheel += float(e.wheel.y);
            io.MouseWheelH += float(e.wheel.x);
            return io.WantCaptureMouse;
        case SDL_TEXTINPUT:
            io.AddInputCharactersUTF8(e.text.text);
            return io.WantCaptureKeyboard;
        case SDL_KEYDOWN:
        case SDL_KEYUP: {
            const int code = e.key.keysym.scancode;
            if (code >= 0 && code < int(IM_ARRAYSIZE(io.KeysDown))) io.KeysDown[code] = e.type == SDL_KEYDOWN;
            const Uint16 mod = e.key.keysym.mod;
            io.KeyShift = mod & KMOD_SHIFT, io.KeyCtrl = mod & KMOD_CTRL, io.KeyAlt = mod & KMOD_ALT;
            return io.WantCaptureKeyboard;
        }
        default:
            return false;
    }
#else
    (void)event;
    return false;
#endif
}

}  // namespace engine
