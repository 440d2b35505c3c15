#include "engine/profile/trace.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <numeric>

#include "engine/files/atomic_file.h"

namespace engine {

namespace {

constexpr int kPid = 1;
constexpr int kFrameLoopTid = 1;

const char* categoryName(Trace::Category c) {
    switch (c) {
        case Trace::Category::Frame: return "frame";
        case Trace::Category::Phase: return "phase";
        case Trace::Category::Zone: return "bullet";
        case Trace::Category::Worker: return "worker";
    }
    return "?";
}

// Microseconds, to the nanosecond (the format's unit; fractions are allowed).
double micros(Trace::Clock::duration d) {
    return double(std::chrono::duration_cast<std::chrono::nanoseconds>(d).count()) / 1000.0;
}

nlohmann::json metadata(const char* what, const std::string& name, int tid = kFrameLoopTid) {
    return {{"ph", "M"}, {"name", what}, {"pid", kPid}, {"tid", tid}, {"args", {{"name", name}}}};
}

}  // namespace

Trace::Trace(Clock::time_point origin) : origin_(origin) {}

int Trace::nameId(std::string_view name) {
    const auto it = std::find(names_.begin(), names_.end(), name);
    if (it != names_.end()) return static_cast<int>(it - names_.begin());
    names_.emplace_back(name);
    return static_cast<int>(names_.size()) - 1;
}

int Trace::staticNameId(const char* name) {
    for (const auto& [address, id] : staticNames_)
        if (address == name && names_[id] == name) return id;  // the text too, in case it was not static
    const int id = nameId(name);
    staticNames_.emplace_back(name, id);
    return id;
}

// Each event is dumped as it is made, so a long run never holds the whole trace as a JSON tree.
std::string Trace::json() const {
    std::vector<std::size_t> order(events_.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [this](std::size_t a, std::size_t b) {
        const Event& x = events_[a];
        const Event& y = events_[b];
        return x.begin != y.begin ? x.begin < y.begin : x.duration > y.duration;
    });
    std::string out = "{\"traceEvents\":[\n";
    out += metadata("process_name", "flagsim").dump() + ",\n";
    out += metadata("thread_name", "frame loop").dump();
    int workers = 0;
    for (const Event& e : events_) workers = std::max(workers, e.thread);
    for (int w = 1; w <= workers; ++w)
        out += ",\n" + metadata("thread_name", "cloth worker " + std::to_string(w), kFrameLoopTid + w).dump();
    for (const std::size_t i : order) {
        const Event& e = events_[i];
        nlohmann::json j = {{"ph", "X"},
                            {"name", names_[e.name]},
                            {"cat", categoryName(e.category)},
                            {"ts", micros(e.begin - origin_)},
                            {"dur", micros(e.duration)},
                            {"pid", kPid},
                            {"tid", kFrameLoopTid + e.thread}};
        if (e.frame >= 0) j["args"] = {{"frame", e.frame}};
        out += ",\n" + j.dump();
    }
    out += "\n],\"displayTimeUnit\":\"ms\"}\n";
    return out;
}

bool Trace::write(const std::string& path, std::string* error) const {
    return writeFileAtomically(path, json(), error);
}

}  // namespace engine
