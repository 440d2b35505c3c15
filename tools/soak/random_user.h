#pragma once
// A user at random, from a seed: gestures of a few events over a few frames, the way a person
// plays with the live demo. Keys held and released (never Escape: the user does not quit),
// the gamepad plugged in, moved and pulled out, clicks on the panel's widgets (its buttons,
// radio buttons, headers), sliders dragged past their ends, numbers typed into its fields (valid,
// out of range, not numbers), camera drags and the wheel outside it. The same seed and the same
// frames give the same events.

#include <cstdint>
#include <functional>
#include <map>
#include <random>
#include <string>

#include "engine/runtime.h"
#include "virtual_pad.h"

namespace soak {

class RandomUser {
public:
    RandomUser(std::uint64_t seed, VirtualPad& pad) : rng_(seed), pad_(pad) {}

    // This frame's events (push them before rt.frame()): the steps of the gestures under way, and
    // perhaps a new gesture.
    void act(const engine::Runtime& rt);
    // A new run: the gestures under way are dropped (the keys they hold were the old window's),
    // and the gamepad pulled out.
    void restart();
    const std::string& gesture() const { return gesture_; }  // the last begun, for reports
    // The gestures made so far by kind (hold, click, drag, type, orbit, wheel, plug, unplug, move).
    const std::map<std::string, long>& counts() const { return counts_; }

private:
    using Step = std::function<void(const engine::Runtime&)>;
    void later(int frames, Step step) { steps_.emplace(frame_ + frames, std::move(step)); }
    void begin(const engine::Runtime& rt);
    void holdKey();
    void clickWidget(const engine::Runtime& rt);
    void dragSlider(const engine::Runtime& rt);
    void typeNumber(const engine::Runtime& rt);
    void orbit(const engine::Runtime& rt);
    void wheel();
    void movePad();
    std::string numberText(double current);
    int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
    double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }

    std::mt19937_64 rng_;
    VirtualPad& pad_;
    int frame_ = 0, busyUntil_ = 0;  // a widget gesture at a time (keys and the pad overlap it)
    std::multimap<int, Step> steps_;
    std::string gesture_;
    std::map<std::string, long> counts_;
};

}  // namespace soak
