#pragma once
// What the soak watches besides the frames: the process's resident memory, the frame times (a
// fixed histogram: bounded however long the soak runs), and a watchdog thread for a frame that
// never ends.

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace soak {

// The resident set of this process, in KiB (from /proc/self/statm); after returning the freed
// heap to the system, so that what is measured is what is still held.
long residentKiB();

// Frame times in 0.1 ms bins up to 2 s (beyond: the last bin), and the longest exactly.
class FrameTimes {
public:
    void add(double ms);
    long count() const { return count_; }
    double percentile(double p) const;  // the bin's upper edge, ms
    double max() const { return max_; }

private:
    static constexpr int kBins = 20000;
    std::array<long, kBins> bins_{};
    long count_ = 0;
    double max_ = 0;
};

// Ends the process with exit code 3 and a report when no beat came for `seconds`: a frame that
// hangs cannot be stopped from its own thread.
class Watchdog {
public:
    explicit Watchdog(double seconds);
    ~Watchdog();
    Watchdog(const Watchdog&) = delete;
    Watchdog& operator=(const Watchdog&) = delete;
    // Alive; `where` says what runs next (the report names it if it never returns).
    void beat(const std::string& where);

private:
    void watch();
    using Clock = std::chrono::steady_clock;
    const std::chrono::duration<double> limit_;
    std::mutex mutex_;
    std::condition_variable wake_;
    Clock::time_point last_ = Clock::now();
    std::string where_ = "starting";
    bool stop_ = false;
    std::thread thread_;
};

}  // namespace soak
