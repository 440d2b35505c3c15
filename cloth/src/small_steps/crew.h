#pragma once
// The step's threads as one runner of parallel loops (ParallelFor) while thread 0 runs the step's
// contact: the other threads, which would wait at the next barrier, serve its loops instead. Each
// loop is split by its size and the crew's thread count alone, one chunk per thread, and each
// chunk is claimed once, by whichever thread gets to it first: thread 0 claims every chunk that
// no other has started, so a thread off its core (the other core busy) costs a loop no wait
// unless it is inside its chunk (as ThreadPool's regions). A thread taken off its core inside its
// chunk keeps thread 0 waiting for the rest of a time slice: after one such wait (over kLate)
// thread 0 runs the session's remaining loops alone, and late() tells the step's lag guard. A
// session is one contact: thread 0 opens it, runs its loops and closes it; the others serve it from
// when they arrive until it closes. Sessions are numbered, so that a thread that arrives late
// serves its own session and never the next.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <thread>

#include "chunk_claims.h"
#include "cloth/parallel_for.h"

namespace cloth {

class Crew final : public ParallelFor {
public:
    using Clock = std::chrono::steady_clock;
    static constexpr std::chrono::microseconds kLate{200};

    explicit Crew(int threads) : threads_(threads) {}
    int threads() const override { return threads_; }

    // Thread 0: session `session` (1, 2, ... within the crew's life) begins.
    void open(std::uint32_t session) {
        alone_ = false, late_ = Clock::duration::zero();
        word_.store(std::uint64_t(session) << 32, std::memory_order_release);
    }
    // Thread 0, between open and close: fn over [0, n), with whichever threads serve.
    void run(int n, const std::function<void(int, int)>& fn) override {
        if (threads_ == 1 || n < 2 * threads_ || alone_) return fn(0, n);
        chunks_.post(n, fn);
        word_.fetch_add(2, std::memory_order_acq_rel);
        chunks_.claim();
        if (chunks_.finished()) return;
        const Clock::time_point t0 = Clock::now();
        for (int spins = 0; !chunks_.finished(); ++spins)
            if (spins > 1000) std::this_thread::yield();
        if (const Clock::duration waited = Clock::now() - t0; waited > kLate) alone_ = true, late_ += waited;
    }
    // Thread 0: this session's waits for a thread off its core (each over kLate).
    Clock::duration late() const { return late_; }
    // Thread 0: the session's loops are done; its servers return.
    void close() { word_.fetch_or(1, std::memory_order_acq_rel); }
    // A thread other than 0: serves session `session`'s loops until it closes (waiting for it to
    // open if thread 0 has not yet).
    void serve(std::uint32_t session) {
        std::uint64_t seen = std::uint64_t(session) << 32;
        for (int spins = 0;; ++spins) {
            const std::uint64_t w = word_.load(std::memory_order_acquire);
            if ((w >> 32) == session && (w & ~std::uint64_t(1)) != seen) seen = w & ~std::uint64_t(1), chunks_.claim(), spins = 0;
            if ((w >> 32) == session && (w & 1)) return;
            if (spins > 1000) std::this_thread::yield();
        }
    }

private:
    const int threads_;
    bool alone_ = false;  // thread 0 runs the session's loops alone (it waited late)
    Clock::duration late_{};
    ChunkClaims chunks_{threads_};
    // The session (high 32 bits), its loops so far times two, and 1 once it has closed.
    std::atomic<std::uint64_t> word_{0};
};

}  // namespace cloth
