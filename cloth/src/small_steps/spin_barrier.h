#pragma once
// A barrier for a few threads that meet thousands of times a second (the small_steps solver's
// substeps): each spins on a generation counter, yielding after kSpinsBeforeYield spins (tens of
// microseconds) so that a descheduled partner gets the core back. No system call in the common
// case: at 65x65 a partner a few microseconds behind is common, and a waiting thread that yielded
// sooner would go into the scheduler at most barriers (docs/performance.md, The stiff flag at
// 65x65 on two threads).

#include <atomic>
#include <thread>

namespace cloth {

class SpinBarrier {
public:
    explicit SpinBarrier(int threads) : threads_(threads) {}
    void wait() {
        const unsigned generation = generation_.load(std::memory_order_acquire);
        if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == threads_) {
            arrived_.store(0, std::memory_order_relaxed);
            generation_.fetch_add(1, std::memory_order_acq_rel);  // releases the others
            return;
        }
        for (int spins = 0; generation_.load(std::memory_order_acquire) == generation; ++spins)
            if (spins > kSpinsBeforeYield) std::this_thread::yield();
    }

private:
    static constexpr int kSpinsBeforeYield = 20000;
    const int threads_;
    std::atomic<int> arrived_{0};
    std::atomic<unsigned> generation_{0};
};

}  // namespace cloth
