#pragma once
// Driving actions and scripted input: a timeline of keyframes (time, throttle, brake, steer,
// handbrake) sampled with linear or step interpolation. Recorded live input is written as a
// step-interpolated script with one keyframe per frame, so it replays to identical frames.
//
// File format (JSON):
//   { "interpolation": "linear" | "step",
//     "keyframes": [ { "t": 0.0, "throttle": 1.0, "brake": 0.0, "steer": 0.0, "handbrake": 0.0 },
//                    ... ],
//     "events": [ { "frame": 120, "command": "solver", "value": "multigrid" }, ... ] }
// Times strictly increasing from >= 0; throttle and steer in [-1, 1]; brake and handbrake in
// [0, 1]. Absent action fields are 0. Events (optional; engine/scene/command.h) are applied at the
// start of their frame, in the order listed; frames do not decrease.

#include <string>
#include <vector>

#include "engine/scene/command.h"

namespace engine {

struct Actions {
    double throttle = 0;   // -1..1, negative reverses
    double brake = 0;      // 0..1
    double steer = 0;      // -1..1, positive turns left
    double handbrake = 0;  // 0..1
    bool operator==(const Actions&) const = default;
};

class InputScript {
public:
    enum class Interpolation { Linear, Step };
    struct Keyframe {
        double t = 0;
        Actions actions;
    };
    struct Event {
        int frame = 0;
        Command command;
        bool operator==(const Event&) const = default;
    };

    // Throws ConfigError naming the file, the field and the value.
    static InputScript load(const std::string& path);
    // The same from text that came from `path` (used in messages only).
    static InputScript parse(const std::string& text, const std::string& path);
    static InputScript fromKeyframes(std::vector<Keyframe> keyframes, Interpolation mode,
                                     std::vector<Event> events = {});
    // Writes to a temporary file and renames it into place. Returns false with *error set.
    bool save(const std::string& path, std::string* error) const;

    Actions sample(double t) const;
    double duration() const { return keys_.empty() ? 0 : keys_.back().t; }
    const std::vector<Keyframe>& keyframes() const { return keys_; }
    const std::vector<Event>& events() const { return events_; }
    // The commands of frame `frame`, in order.
    std::vector<Command> commandsAt(int frame) const;
    Interpolation interpolation() const { return mode_; }

private:
    std::vector<Keyframe> keys_;
    std::vector<Event> events_;
    Interpolation mode_ = Interpolation::Linear;
};

// Records the actions applied each frame and the commands applied at each frame's start;
// `script()` replays them exactly. While the simulation is paused the time stands still: the
// actions of the last frame at a time are the ones its ticks used.
class InputRecorder {
public:
    void record(double t, const Actions& a);
    void record(int frame, const Command& c);
    InputScript script() const;

private:
    std::vector<InputScript::Keyframe> keys_;
    std::vector<InputScript::Event> events_;
};

}  // namespace engine
