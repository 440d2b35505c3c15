#pragma once
// A parallel loop's chunks as threads claim them (ThreadPool's regions, small_steps' crew): [0, n)
// cut into `parts` chunks by n and parts alone, each claimed once, by whichever thread gets to it
// first. A thread that claims after the loop's last chunk finds none and returns; one that claims
// after the next loop is posted runs that loop's chunk (it reads the job after its claim).

#include <atomic>
#include <cstdint>
#include <functional>

namespace cloth {

struct ChunkClaims {
    explicit ChunkClaims(int parts) : parts(parts) {}

    // A new loop: publishes the job and n to the threads that claim from now on.
    void post(int count, const std::function<void(int, int)>& fn) {
        job = &fn, n = count;
        done.store(0, std::memory_order_relaxed);
        next.store(0, std::memory_order_release);
    }
    // Runs chunks until none is left to claim: each(c, begin, end) runs chunk c.
    template <class Each>
    void claim(Each each) {
        for (int c; (c = next.fetch_add(1, std::memory_order_acq_rel)) < parts;) {
            each(c, int(std::int64_t(n) * c / parts), int(std::int64_t(n) * (c + 1) / parts));
            done.fetch_add(1, std::memory_order_acq_rel);
        }
    }
    void claim() {
        claim([this](int, int begin, int end) { (*job)(begin, end); });
    }
    bool finished() const { return done.load(std::memory_order_acquire) == parts; }

    const int parts;
    const std::function<void(int, int)>* job = nullptr;
    int n = 0;

private:
    std::atomic<int> next{1 << 30};  // the next chunk to claim (past parts: none left)
    std::atomic<int> done{0};        // chunks finished
};

}  // namespace cloth
