#pragma once
// A parallel loop, as a component takes it: run(n, fn) calls fn(begin, end) once for each chunk of
// [0, n), the chunks together covering it exactly once, on whichever threads the runner has, and
// returns when all are done. A loop that writes only its own indices gives the same bits for any
// runner and any split (ThreadPool, the library's; small_steps' threads while one of them runs the
// step's contact).

#include <functional>

namespace cloth {

class ParallelFor {
public:
    virtual ~ParallelFor() = default;
    virtual void run(int n, const std::function<void(int, int)>& fn) = 0;
    // How many threads may run chunks at once (1: fn(0, n) on the calling thread).
    virtual int threads() const = 0;
};

// fn(begin, end) over [0, n): on the runner's threads, or all here when there is none.
inline void forChunks(ParallelFor* loops, int n, const std::function<void(int, int)>& fn) {
    if (loops) loops->run(n, fn);
    else fn(0, n);
}

// Whether `loops` runs chunks on more than one thread.
inline bool parallel(const ParallelFor* loops) { return loops && loops->threads() > 1; }

}  // namespace cloth
