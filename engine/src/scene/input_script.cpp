#include "engine/scene/input_script.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "scene/json_fields.h"
#include "engine/files/atomic_file.h"

namespace engine {

namespace {
InputScript scriptFromJson(const nlohmann::json& root, const std::string& path);
}

namespace {

// The "events" list: frames that do not decrease, each command valid.
std::vector<InputScript::Event> readEvents(const JsonFields& top) {
    std::vector<InputScript::Event> events;
    if (!top.has("events")) return events;
    const nlohmann::json& list = top.at("events");
    if (!list.is_array()) top.fail("events", list, "must be an array of events");
    for (std::size_t i = 0; i < list.size(); ++i) {
        JsonFields e(top.file(), list[i], "events[" + std::to_string(i) + "]");
        e.allowOnly({"frame", "command", "value"});
        if (!e.has("frame")) e.fail(e.pathOf("frame"), nullptr, "missing (every event needs a frame)");
        if (!e.has("command")) e.fail(e.pathOf("command"), nullptr, "missing (every event needs a command)");
        InputScript::Event ev;
        ev.frame = e.integer("frame", 0, 0, 100000000);
        if (!events.empty() && ev.frame < events.back().frame)
            e.fail(e.pathOf("frame"), list[i]["frame"],
                   "frames must not decrease (previous event is at frame " + std::to_string(events.back().frame) + ")");
        ev.command.name = e.string("command", "");
        ev.command.value = e.string("value", "");
        const std::string why = checkCommand(ev.command);
        if (why.rfind("unknown command", 0) == 0) e.fail(e.pathOf("command"), list[i]["command"], why);
        if (!why.empty()) e.fail(e.pathOf("value"), e.has("value") ? list[i]["value"] : nlohmann::json(nullptr), why);
        events.push_back(std::move(ev));
    }
    return events;
}

}  // namespace

InputScript InputScript::load(const std::string& path) {
    return scriptFromJson(JsonFields::parseFile(path), path);
}

InputScript InputScript::parse(const std::string& text, const std::string& path) {
    return scriptFromJson(JsonFields::parseText(text, path), path);
}

namespace {
InputScript scriptFromJson(const nlohmann::json& root, const std::string& path) {
    using Keyframe = InputScript::Keyframe;
    using Interpolation = InputScript::Interpolation;
    JsonFields top(path, root);
    top.allowOnly({"interpolation", "keyframes", "events", "description"});
    top.string("description", "");
    const std::string mode = top.oneOf("interpolation", "linear", {"linear", "step"});
    if (!top.has("keyframes")) throw ConfigError(path + ": keyframes: missing (a script needs a timeline)");
    const nlohmann::json& list = top.at("keyframes");
    if (!list.is_array()) top.fail("keyframes", list, "must be an array of keyframes");
    if (list.empty()) top.fail("keyframes", list, "is empty: a script needs at least one keyframe");
    std::vector<Keyframe> keys;
    for (std::size_t i = 0; i < list.size(); ++i) {
        JsonFields k(path, list[i], "keyframes[" + std::to_string(i) + "]");
        k.allowOnly({"t", "throttle", "brake", "steer", "handbrake"});
        if (!k.has("t")) k.fail(k.pathOf("t"), nullptr, "missing (every keyframe needs a time)");
        Keyframe kf;
        kf.t = k.number("t", 0, 0, 1e6);
        if (!keys.empty() && kf.t <= keys.back().t)
            k.fail(k.pathOf("t"), list[i]["t"],
                   "times must increase (previous keyframe is at t = " +
                       std::to_string(keys.back().t) + ")");
        kf.actions.throttle = k.number("throttle", 0, -1, 1);
        kf.actions.brake = k.number("brake", 0, 0, 1);
        kf.actions.steer = k.number("steer", 0, -1, 1);
        kf.actions.handbrake = k.number("handbrake", 0, 0, 1);
        keys.push_back(kf);
    }
    return InputScript::fromKeyframes(std::move(keys), mode == "step" ? Interpolation::Step : Interpolation::Linear,
                                      readEvents(top));
}
}  // namespace

InputScript InputScript::fromKeyframes(std::vector<Keyframe> keyframes, Interpolation mode,
                                      std::vector<Event> events) {
    InputScript s;
    s.keys_ = std::move(keyframes);
    s.events_ = std::move(events);
    s.mode_ = mode;
    return s;
}

std::vector<Command> InputScript::commandsAt(int frame) const {
    std::vector<Command> out;
    const auto first = std::lower_bound(events_.begin(), events_.end(), frame,
                                        [](const Event& e, int f) { return e.frame < f; });
    for (auto e = first; e != events_.end() && e->frame == frame; ++e) out.push_back(e->command);
    return out;
}

Actions InputScript::sample(double t) const {
    if (keys_.empty()) return {};
    if (t <= keys_.front().t) return keys_.front().actions;
    if (t >= keys_.back().t) return keys_.back().actions;
    // First keyframe strictly after t; the one before it is at or before t.
    const auto next = std::upper_bound(keys_.begin(), keys_.end(), t,
                                       [](double time, const Keyframe& k) { return time < k.t; });
    const Keyframe& a = *(next - 1);
    if (mode_ == Interpolation::Step) return a.actions;
    const Keyframe& b = *next;
    const double s = (t - a.t) / (b.t - a.t);
    auto lerp = [s](double x, double y) { return x + s * (y - x); };
    return {lerp(a.actions.throttle, b.actions.throttle), lerp(a.actions.brake, b.actions.brake),
            lerp(a.actions.steer, b.actions.steer), lerp(a.actions.handbrake, b.actions.handbrake)};
}

bool InputScript::save(const std::string& path, std::string* error) const {
    nlohmann::json root;
    root["interpolation"] = mode_ == Interpolation::Step ? "step" : "linear";
    nlohmann::json list = nlohmann::json::array();
    for (const Keyframe& k : keys_)
        list.push_back({{"t", k.t},
                        {"throttle", k.actions.throttle},
                        {"brake", k.actions.brake},
                        {"steer", k.actions.steer},
                        {"handbrake", k.actions.handbrake}});
    root["keyframes"] = std::move(list);
    if (!events_.empty()) {
        nlohmann::json events = nlohmann::json::array();
        for (const Event& e : events_) {
            nlohmann::json one = {{"frame", e.frame}, {"command", e.command.name}};
            if (!e.command.value.empty()) one["value"] = e.command.value;
            events.push_back(std::move(one));
        }
        root["events"] = std::move(events);
    }
    // Doubles are written so that they read back exactly.
    return writeFileAtomically(path, root.dump(1) + "\n", error);
}

void InputRecorder::record(double t, const Actions& a) {
    // A paused frame at the same time replaces the last keyframe: its ticks, when they come,
    // use the actions of the last frame at this time.
    if (!keys_.empty() && keys_.back().t == t) {
        keys_.back().actions = a;
        if (keys_.size() > 1 && keys_[keys_.size() - 2].actions == a) keys_.pop_back();
        return;
    }
    // Only changes need a keyframe under step interpolation (and the first frame).
    if (!keys_.empty() && keys_.back().actions == a) return;
    keys_.push_back({t, a});
}

void InputRecorder::record(int frame, const Command& c) { events_.push_back({frame, c}); }

InputScript InputRecorder::script() const {
    std::vector<InputScript::Keyframe> keys = keys_;
    if (keys.empty()) keys.push_back({0, {}});
    return InputScript::fromKeyframes(std::move(keys), InputScript::Interpolation::Step, events_);
}

}  // namespace engine
