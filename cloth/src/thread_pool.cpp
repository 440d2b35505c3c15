#include "cloth/thread_pool.h"

namespace cloth {

namespace {
void chunk(int n, int parts, int index, int& begin, int& end) {
    begin = static_cast<int>(static_cast<long long>(n) * index / parts);
    end = static_cast<int>(static_cast<long long>(n) * (index + 1) / parts);
}
}  // namespace

ThreadPool::ThreadPool(int threads) : threads_(threads < 1 ? 1 : threads), spans_(std::size_t(threads_)) {
    for (int i = 1; i < threads_; ++i) workers_.emplace_back([this, i] { worker(i); });
}

ThreadPool::~ThreadPool() {
    stop_.store(true, std::memory_order_release);
    generation_.fetch_add(1, std::memory_order_acq_rel);
    generation_.notify_all();
    for (auto& t : workers_) t.join();
}

void ThreadPool::run(int n, const std::function<void(int, int)>& fn) {
    if (threads_ == 1 || n < 2 * threads_) {
        fn(0, n);
        return;
    }
    job_ = &fn;
    n_ = n;
    timed_ = bool(observer_);
    pending_.store(threads_ - 1, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_acq_rel);  // publishes job_ and n_
    generation_.notify_all();
    int begin, end;
    chunk(n, threads_, 0, begin, end);
    fn(begin, end);
    for (int spins = 0; pending_.load(std::memory_order_acquire) != 0; ++spins)
        if (spins > 1000) std::this_thread::yield();
    if (timed_)
        for (int w = 1; w < threads_; ++w) observer_(w, spans_[std::size_t(w)].begin, spans_[std::size_t(w)].end);
}

void ThreadPool::worker(int index) {
    unsigned seen = 0;
    for (;;) {
        // Spin for a while (the next region usually follows within tens of microseconds: a
        // Newton step's serial parts between its regions last that long), then sleep in the
        // kernel so an idle pool costs no CPU (the renderer needs that core).
        unsigned g = generation_.load(std::memory_order_acquire);
        const Clock::time_point until = Clock::now() + kSpin;
        for (int spins = 1; g == seen; ++spins) {
            g = generation_.load(std::memory_order_acquire);
            if (spins % 256 == 0 && Clock::now() > until) break;
        }
        while (g == seen) {
            generation_.wait(seen, std::memory_order_acquire);
            g = generation_.load(std::memory_order_acquire);
        }
        seen = g;
        if (stop_.load(std::memory_order_acquire)) return;
        int begin, end;
        chunk(n_, threads_, index, begin, end);
        if (timed_) spans_[std::size_t(index)].begin = Clock::now();
        (*job_)(begin, end);
        if (timed_) spans_[std::size_t(index)].end = Clock::now();
        pending_.fetch_sub(1, std::memory_order_acq_rel);
    }
}

}  // namespace cloth
