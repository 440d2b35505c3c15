#pragma once
// Whether a parallel step's threads run together: its other threads must all have begun before
// thread 0 (the lead) starts the substeps, for they meet at barriers. A thread that has not begun
// within the lead's wait (a worker still asleep, off its core, or a host's task not yet run) is
// given up: its share goes to the lead, which then runs the step alone (the same bits), and the
// thread, when it does begin, returns at once. Threads that had begun wait for the lead's answer.

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

namespace cloth {

class StartGate {
public:
    using Clock = std::chrono::steady_clock;

    // A new step for `threads` threads: none has begun.
    void open(int threads) {
        if (threads != threads_) slots_ = std::make_unique<std::atomic<int>[]>(std::size_t(threads)), threads_ = threads;
        for (int t = 0; t < threads; ++t) slots_[std::size_t(t)].store(kWaiting, std::memory_order_relaxed);
        answer_.store(kWaiting, std::memory_order_release);
    }
    // Thread t (> 0) begins: true when the step runs together, false when the lead took its share.
    bool join(int t) {
        int waiting = kWaiting;
        if (!slots_[std::size_t(t)].compare_exchange_strong(waiting, kBegun, std::memory_order_acq_rel)) return false;
        for (int spins = 0; answer_.load(std::memory_order_acquire) == kWaiting; ++spins)
            if (spins > 2000) std::this_thread::yield();
        return answer_.load(std::memory_order_acquire) == kTogether;
    }
    // The lead: waits up to `wait` for every other thread to begin, gives up those that have not,
    // and answers. True: together.
    bool lead(Clock::duration wait) {
        const Clock::time_point until = Clock::now() + wait;
        for (int spins = 0; !allBegun(); ++spins)
            if (spins % 64 == 0 && Clock::now() > until) break;
        bool together = true;
        for (int t = 1; t < threads_; ++t) {
            int waiting = kWaiting;
            if (slots_[std::size_t(t)].compare_exchange_strong(waiting, kGivenUp, std::memory_order_acq_rel)) together = false;
        }
        answer_.store(together ? kTogether : kAlone, std::memory_order_release);
        return together;
    }

private:
    static constexpr int kWaiting = 0, kBegun = 1, kGivenUp = 2, kTogether = 3, kAlone = 4;
    bool allBegun() const {
        for (int t = 1; t < threads_; ++t)
            if (slots_[std::size_t(t)].load(std::memory_order_acquire) != kBegun) return false;
        return true;
    }
    int threads_ = 0;
    std::unique_ptr<std::atomic<int>[]> slots_;
    std::atomic<int> answer_{kWaiting};
};

}  // namespace cloth
