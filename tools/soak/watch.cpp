#include "watch.h"

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <unistd.h>

namespace soak {

long residentKiB() {
    malloc_trim(0);
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    statm >> pages >> resident;
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

void FrameTimes::add(double ms) {
    ++bins_[std::size_t(std::clamp(int(ms * 10), 0, kBins - 1))];
    ++count_;
    max_ = std::max(max_, ms);
}

double FrameTimes::percentile(double p) const {
    const long rank = std::max(1L, long(std::ceil(p * count_)));
    long seen = 0;
    for (int b = 0; b < kBins; ++b)
        if ((seen += bins_[std::size_t(b)]) >= rank) return std::min((b + 1) / 10.0, max_);
    return max_;
}

Watchdog::Watchdog(double seconds) : limit_(seconds), thread_([this] { watch(); }) {}

Watchdog::~Watchdog() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void Watchdog::beat(const std::string& where) {
    std::lock_guard<std::mutex> lock(mutex_);
    last_ = Clock::now();
    where_ = where;
}

void Watchdog::watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
        wake_.wait_for(lock, std::chrono::milliseconds(500));
        if (stop_ || Clock::now() - last_ < limit_) continue;
        std::fprintf(stderr, "\nflagsim_soak: FAIL: hang: nothing finished for %.0f s; it was running: %s\n",
                     limit_.count(), where_.c_str());
        std::fflush(stderr);
        std::_Exit(3);
    }
}

}  // namespace soak
