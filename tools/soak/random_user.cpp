#include "random_user.h"

#include <SDL.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "cloth/solver.h"
#include "cloth/solver_config.h"

namespace soak {

namespace {

Uint32 windowId() { return SDL_GetWindowID(SDL_GL_GetCurrentWindow()); }

void key(Uint32 type, SDL_Scancode code, Uint16 mod = 0) {
    SDL_Event e{};
    e.type = type;
    e.key.windowID = windowId();
    e.key.state = type == SDL_KEYDOWN ? SDL_PRESSED : SDL_RELEASED;
    e.key.keysym.scancode = code;
    e.key.keysym.sym = SDL_GetKeyFromScancode(code);
    e.key.keysym.mod = mod;
    SDL_PushEvent(&e);
}

void motion(int x, int y, int dx = 0, int dy = 0) {
    SDL_Event e{};
    e.type = SDL_MOUSEMOTION;
    e.motion.windowID = windowId();
    e.motion.x = x, e.motion.y = y, e.motion.xrel = dx, e.motion.yrel = dy;
    SDL_PushEvent(&e);
}

void button(Uint32 type, int x, int y) {
    SDL_Event e{};
    e.type = type;
    e.button.windowID = windowId();
    e.button.button = SDL_BUTTON_LEFT;
    e.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
    e.button.clicks = 1;
    e.button.x = x, e.button.y = y;
    SDL_PushEvent(&e);
}

void text(const std::string& s) {
    SDL_Event e{};
    e.type = SDL_TEXTINPUT;
    e.text.windowID = windowId();
    std::strncpy(e.text.text, s.c_str(), sizeof e.text.text - 1);
    SDL_PushEvent(&e);
}

const std::array<const char*, 8> kSliders = {"stretch N/m", "shear N/m", "bend N/m", "mass kg",
                                             "wind x m/s", "wind y m/s", "wind z m/s", "air density"};

bool isSlider(const std::string& label) {
    return std::find(kSliders.begin(), kSliders.end(), label) != kSliders.end();
}

// Drawn within the window (the panel may run below its bottom edge).
bool visible(const engine::Runtime& rt, const std::string& label) {
    const auto r = rt.widgetRect(label);
    return r && (*r)[0] >= 0 && (*r)[1] >= 0 && (*r)[2] <= float(rt.scene().render.width) &&
           (*r)[3] <= float(rt.scene().render.height);
}

// The panel's number fields now: the running solver's numeric keys, and the sliders (which take
// a typed number after a ctrl+click).
std::vector<std::string> numberFields(const engine::Runtime& rt) {
    std::vector<std::string> fields;
    for (const cloth::SolverKeyInfo& k : cloth::solverKeys(rt.scene().flag.solver))
        if (k.type != cloth::SolverKeyInfo::Type::Choice && visible(rt, k.name)) fields.push_back(k.name);
    for (const char* s : kSliders)
        if (visible(rt, s)) fields.push_back(s);
    return fields;
}

// What the field shows now.
double currentValue(const engine::Runtime& rt, const std::string& label) {
    const engine::SceneConfig& s = rt.scene();
    if (label == "stretch N/m") return s.flag.stiffness.structural;
    if (label == "shear N/m") return s.flag.stiffness.shear;
    if (label == "bend N/m") return s.flag.stiffness.bend;
    if (label == "mass kg") return s.flag.mass;
    if (label == "air density") return s.air.density;
    if (label.rfind("wind ", 0) == 0) return s.air.wind[label[5] - 'x'];
    for (const cloth::SolverKeyInfo& k : cloth::solverKeys(s.flag.solver))
        if (k.name == label) return k.value;
    return 1;
}

std::array<int, 2> centre(const std::array<float, 4>& r) { return {int((r[0] + r[2]) / 2), int((r[1] + r[3]) / 2)}; }

// The rightmost edge of the panel's widgets: the scene is to its right.
int panelRight(const engine::Runtime& rt) {
    float right = 0;
    for (const std::string& label : rt.widgetLabels()) right = std::max(right, (*rt.widgetRect(label))[2]);
    return int(right);
}

}  // namespace

void RandomUser::restart() {
    steps_.clear();
    pad_.unplug();
    busyUntil_ = frame_;
}

void RandomUser::act(const engine::Runtime& rt) {
    for (auto it = steps_.begin(); it != steps_.end() && it->first <= frame_; it = steps_.erase(it)) it->second(rt);
    if (frame_ >= busyUntil_ && uniform(0, 9) < 3) begin(rt);
    ++frame_;
}

// One gesture, chosen by weight; a widget gesture keeps the mouse busy until it ends.
void RandomUser::begin(const engine::Runtime& rt) {
    const std::string last = gesture_;
    gesture_.clear();
    const int pick = uniform(0, 99);
    if (pick < 25) holdKey();
    else if (pick < 50) clickWidget(rt);
    else if (pick < 60) dragSlider(rt);
    else if (pick < 75) typeNumber(rt);
    else if (pick < 85) orbit(rt);
    else if (pick < 90) wheel();
    else movePad();
    if (gesture_.empty()) gesture_ = last;  // nothing to do it on (no such widget in view)
    else ++counts_[gesture_.substr(0, gesture_.find(' '))];
}

void RandomUser::holdKey() {
    static const SDL_Scancode keys[] = {SDL_SCANCODE_UP, SDL_SCANCODE_DOWN, SDL_SCANCODE_LEFT, SDL_SCANCODE_RIGHT,
                                        SDL_SCANCODE_W,  SDL_SCANCODE_A,    SDL_SCANCODE_S,    SDL_SCANCODE_D,
                                        SDL_SCANCODE_SPACE};
    const SDL_Scancode code = keys[uniform(0, 8)];
    gesture_ = std::string("hold ") + SDL_GetScancodeName(code);
    key(SDL_KEYDOWN, code);
    later(uniform(1, 180), [code](const engine::Runtime&) { key(SDL_KEYUP, code); });
}

// Move, press, release, a frame each, at the widget's centre when each step runs.
void RandomUser::clickWidget(const engine::Runtime& rt) {
    std::vector<std::string> labels = rt.widgetLabels();
    std::erase_if(labels, [&rt](const std::string& l) { return !visible(rt, l); });
    if (labels.empty()) return;
    const std::string label = labels[std::size_t(uniform(0, int(labels.size()) - 1))];
    gesture_ = "click " + label;
    const Uint32 types[3] = {SDL_MOUSEMOTION, SDL_MOUSEBUTTONDOWN, SDL_MOUSEBUTTONUP};
    for (int k = 0; k < 3; ++k)
        later(k, [label, type = types[k]](const engine::Runtime& r) {
            const auto rect = r.widgetRect(label);
            if (!rect) return;
            const auto [x, y] = centre(*rect);
            if (type == SDL_MOUSEMOTION) motion(x, y);
            else button(type, x, y);
        });
    busyUntil_ = frame_ + 3;
}

// Press on a slider, move past one end (or to a point within) over a few frames, release.
void RandomUser::dragSlider(const engine::Runtime& rt) {
    const std::string label = kSliders[std::size_t(uniform(0, int(kSliders.size()) - 1))];
    const auto rect = rt.widgetRect(label);
    if (!rect || !visible(rt, label)) return;
    const auto at = centre(*rect);
    const int x0 = at[0], y = at[1];  // plain names: clang cannot capture a structured binding
    const int x1 = uniform(0, 2) == 0 ? int((*rect)[0]) - 40 : uniform(0, 1) ? int((*rect)[2]) + 40
                                                                           : uniform(int((*rect)[0]), int((*rect)[2]));
    gesture_ = "drag " + label + " to x=" + std::to_string(x1);
    motion(x0, y);
    later(1, [x0, y](const engine::Runtime&) { button(SDL_MOUSEBUTTONDOWN, x0, y); });
    const int moves = uniform(1, 6);
    for (int k = 1; k <= moves; ++k) {
        const int x = x0 + (x1 - x0) * k / moves, dx = (x1 - x0) / moves;
        later(1 + k, [x, y, dx](const engine::Runtime&) { motion(x, y, dx); });
    }
    later(2 + moves, [x1, y](const engine::Runtime&) { button(SDL_MOUSEBUTTONUP, x1, y); });
    busyUntil_ = frame_ + 3 + moves;
}

// Into a solver key's field (a click, then ctrl+A) or a slider (ctrl+click): a number, Enter.
void RandomUser::typeNumber(const engine::Runtime& rt) {
    const std::vector<std::string> fields = numberFields(rt);
    if (fields.empty()) return;
    const std::string label = fields[std::size_t(uniform(0, int(fields.size()) - 1))];
    const std::string value = numberText(currentValue(rt, label));
    gesture_ = "type '" + value + "' into " + label;
    const bool slider = isSlider(label);
    auto at = [label](const engine::Runtime& r, const std::function<void(int, int)>& f) {
        if (const auto rect = r.widgetRect(label)) {
            const auto [x, y] = centre(*rect);
            f(x, y);
        }
    };
    int t = 0;
    later(t++, [at](const engine::Runtime& r) { at(r, [](int x, int y) { motion(x, y); }); });
    if (slider) later(t++, [](const engine::Runtime&) { key(SDL_KEYDOWN, SDL_SCANCODE_LCTRL, KMOD_LCTRL); });
    later(t++, [at](const engine::Runtime& r) { at(r, [](int x, int y) { button(SDL_MOUSEBUTTONDOWN, x, y); }); });
    later(t++, [at](const engine::Runtime& r) { at(r, [](int x, int y) { button(SDL_MOUSEBUTTONUP, x, y); }); });
    if (slider) {
        later(t++, [](const engine::Runtime&) { key(SDL_KEYUP, SDL_SCANCODE_LCTRL, 0); });
    } else {  // select what the field holds
        later(t++, [](const engine::Runtime&) { key(SDL_KEYDOWN, SDL_SCANCODE_A, KMOD_LCTRL); });
        later(t++, [](const engine::Runtime&) { key(SDL_KEYUP, SDL_SCANCODE_A, KMOD_LCTRL); });
    }
    later(t++, [value](const engine::Runtime&) { text(value); });
    later(t++, [](const engine::Runtime&) { key(SDL_KEYDOWN, SDL_SCANCODE_RETURN); });
    later(t++, [](const engine::Runtime&) { key(SDL_KEYUP, SDL_SCANCODE_RETURN); });
    busyUntil_ = frame_ + t;
}

// Mostly near the current value (a tenth to ten times it), sometimes at an edge or not a number.
std::string RandomUser::numberText(double current) {
    static const char* odd[] = {"-1", "0", "nan", "inf", "-inf", "1e30", "abc", "1e-30", "3.5", "1000", "2", "-0"};
    char buf[32];
    if (uniform(0, 3) == 0) return odd[uniform(0, int(std::size(odd)) - 1)];
    const double magnitude = current == 0 ? 1 : std::abs(current);
    std::snprintf(buf, sizeof buf, "%.4g", std::copysign(magnitude, current) * std::pow(10.0, uniform(-1.0, 1.0)));
    return buf;
}

// A drag in the scene, right of the panel: the camera orbits.
void RandomUser::orbit(const engine::Runtime& rt) {
    const int w = rt.scene().render.width, h = rt.scene().render.height, left = panelRight(rt) + 20;
    if (left > w - 40) return;
    int x = uniform(left, w - 20), y = uniform(20, h - 20);
    gesture_ = "orbit from " + std::to_string(x) + "," + std::to_string(y);
    motion(x, y);
    later(1, [x, y](const engine::Runtime&) { button(SDL_MOUSEBUTTONDOWN, x, y); });
    const int moves = uniform(1, 10);
    for (int k = 0; k < moves; ++k) {
        const int dx = uniform(-60, 60), dy = uniform(-40, 40);
        x = std::clamp(x + dx, 0, w - 1), y = std::clamp(y + dy, 0, h - 1);
        later(2 + k, [x, y, dx, dy](const engine::Runtime&) { motion(x, y, dx, dy); });
    }
    later(2 + moves, [x, y](const engine::Runtime&) { button(SDL_MOUSEBUTTONUP, x, y); });
    busyUntil_ = frame_ + 3 + moves;
}

void RandomUser::wheel() {
    SDL_Event e{};
    e.type = SDL_MOUSEWHEEL;
    e.wheel.windowID = windowId();
    e.wheel.y = uniform(-3, 3);
    gesture_ = "wheel " + std::to_string(e.wheel.y);
    SDL_PushEvent(&e);
}

// Plug the pad in or pull it out, or move its stick and triggers and press or release A.
void RandomUser::movePad() {
    if (!pad_.plugged() || uniform(0, 9) == 0) {
        gesture_ = pad_.plugged() ? "unplug the gamepad" : "plug a gamepad in";
        if (pad_.plugged()) pad_.unplug();
        else pad_.plug();
        return;
    }
    gesture_ = "move the gamepad";
    pad_.setAxis(SDL_CONTROLLER_AXIS_LEFTX, uniform(-1.0, 1.0));
    pad_.setAxis(SDL_CONTROLLER_AXIS_TRIGGERRIGHT, uniform(0, 1) ? uniform(0.0, 1.0) : 0.0);
    pad_.setAxis(SDL_CONTROLLER_AXIS_TRIGGERLEFT, uniform(0, 3) ? 0.0 : uniform(0.0, 1.0));
    pad_.setButton(SDL_CONTROLLER_BUTTON_A, uniform(0, 4) == 0);
}

}  // namespace soak
