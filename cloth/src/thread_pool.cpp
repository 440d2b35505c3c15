#include "cloth/thread_pool.h"

namespace cloth {

namespace {
void chunk(int n, int parts, int index, int& begin, int& end) {
    begin = static_cast<int>(static_cast<long long>(n) * index / parts);
    end = static_cast<int>(static_cast<long long>(n) * (index + 1) / parts);
}
}  // namespace

ThreadPool::ThreadPool(int threads) : threads_(threads < 1 ? 1 : threads), spans_(std::size_t(threads_)) {
    for (int i = 1; i < threads_; ++i) workers_.emplace_back([this] { worker(); });
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
    for (Span& s : spans_) s.ran = false;
    done_.store(0, std::memory_order_relaxed);
    next_.store(0, std::memory_order_release);  // publishes job_, n_ and the spans
    generation_.fetch_add(1, std::memory_order_acq_rel);
    generation_.notify_all();
    claimChunks();  // chunk 0 first, then any a worker has not started: a late worker costs no wait
    for (int spins = 0; done_.load(std::memory_order_acquire) != threads_; ++spins)
        if (spins > 1000) std::this_thread::yield();
    if (timed_)
        for (int c = 1; c < threads_; ++c)
            if (spans_[std::size_t(c)].ran) observer_(c, spans_[std::size_t(c)].begin, spans_[std::size_t(c)].end);
}

// Runs chunks of the current region until none is left to claim (each is claimed exactly once).
void ThreadPool::claimChunks() {
    for (int c; (c = next_.fetch_add(1, std::memory_order_acq_rel)) < threads_;) {
        int begin, end;
        chunk(n_, threads_, c, begin, end);
        Span& span = spans_[std::size_t(c)];
        if (timed_) span.begin = Clock::now();
        (*job_)(begin, end);
        if (timed_) span.end = Clock::now(), span.ran = true;
        done_.fetch_add(1, std::memory_order_acq_rel);
    }
}

void ThreadPool::worker() {
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
        claimChunks();
    }
}

}  // namespace cloth
