#pragma once
// A timeline of one run for profilers: complete events (begin, duration, name, thread) written
// as Chrome Trace Event JSON, which Perfetto UI and chrome://tracing open. The profiler records
// the frames, the phases it times and Bullet's zones into it; the flag records its own phases
// per step. A run without a trace records nothing: the recorders hold a null pointer.
//
// Events are recorded from the frame loop's thread only. The cloth pool's workers' spans are
// recorded there too, after each parallel region (cloth::ThreadPool::setObserver), on their own
// thread rows ("cloth worker N").

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

namespace engine {

class Trace {
public:
    using Clock = std::chrono::steady_clock;
    enum class Category { Frame, Phase, Zone, Worker };  // "frame", "phase", "bullet", "worker" in the file

    struct Event {
        Clock::time_point begin;
        Clock::duration duration;
        int name;      // into names()
        Category category;
        int frame;     // the frame's index, for Frame events; -1 otherwise
        int thread;    // 0: the frame loop; N: the cloth pool's worker N
    };

    // Timestamps are written in microseconds since origin.
    explicit Trace(Clock::time_point origin = Clock::now());

    // The id of a name (added on first use).
    int nameId(std::string_view name);
    // The same, first looked up by address: for strings with static storage (Bullet's zone names).
    int staticNameId(const char* name);

    void complete(int name, Category category, Clock::time_point begin, Clock::time_point end,
                  int frame = -1, int thread = 0) {
        events_.push_back({begin, end - begin, name, category, frame, thread});
    }

    const std::vector<Event>& events() const { return events_; }
    const std::vector<std::string>& names() const { return names_; }

    // The file's text, {"traceEvents": [...], "displayTimeUnit": "ms"}: the process and thread
    // names ("M"), then the events ("X") by begin time, an enclosing event before what it encloses.
    std::string json() const;
    // Writes json() to path through a temporary name. False with *error set on failure.
    bool write(const std::string& path, std::string* error) const;

private:
    Clock::time_point origin_;
    std::vector<std::string> names_;
    std::vector<std::pair<const char*, int>> staticNames_;
    std::vector<Event> events_;
};

}  // namespace engine
