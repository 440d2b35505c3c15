#pragma once
// A small persistent thread pool for data-parallel loops. `run(n, fn)` splits [0, n) into one
// contiguous chunk per thread; the split depends only on n and the thread count, and each index
// is processed by exactly one call, so a kernel that writes only its own indices gives the same
// bits for any thread count. Each chunk is claimed once, by whichever thread gets to it first: the
// calling thread claims every chunk that no worker has started (usually chunk 0 first), so a
// worker that the scheduler has taken off its core (the other core busy, as in a game) costs the
// region no wait unless it is inside its chunk. Workers spin for up to kSpin between jobs: a cloth step has many
// short parallel regions and a sleeping thread takes longer to wake than a region lasts; after
// that they sleep on the counter (futex), so an idle pool costs nothing. With a host's task system
// (useHost, cloth/task_system.h) the pool starts no thread of its own: each region hands the host
// one helper task per chunk after the first, which claims chunks as a worker would.

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "cloth/parallel_for.h"
#include "cloth/task_system.h"

namespace cloth {

class ThreadPool final : public ParallelFor {
public:
    explicit ThreadPool(int threads);
    ~ThreadPool() override;
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int threads() const override { return threads_; }
    // Calls fn(begin, end) for each chunk; the calling thread takes any chunk not yet claimed.
    // Returns when all are done.
    void run(int n, const std::function<void(int, int)>& fn) override;
    // The host's task system runs the helpers from now on (null: the pool's own threads, started
    // at the next region). Not during run(); the host must outlive its use here.
    void useHost(TaskSystem* host);

    // When each chunk 1 .. threads-1 of a parallel region ran (labelled as worker c), told on the
    // calling thread once the region is done (a profiler's timeline). Null, the default: nothing is timed.
    using Clock = std::chrono::steady_clock;
    using Observer = std::function<void(int worker, Clock::time_point begin, Clock::time_point end)>;
    void setObserver(Observer observer) { observer_ = std::move(observer); }

private:
    static constexpr std::chrono::microseconds kSpin{100};
    struct Region;  // the region being run: shared with the workers and the host's helpers
    void startWorkers();
    void stopWorkers();
    void worker(unsigned seen);
    int threads_;
    TaskSystem* host_ = nullptr;
    std::shared_ptr<Region> region_;
    std::vector<std::thread> workers_;
    std::atomic<unsigned> generation_{0};
    std::atomic<bool> stop_{false};
    Observer observer_;
};

}  // namespace cloth
