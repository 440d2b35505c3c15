#include "cloth/thread_pool.h"

#include "chunk_claims.h"

namespace cloth {

// The region being run. The pool's workers and the host's helpers hold it, so that a helper the
// host runs after its region (or after the pool) finds no chunk left and returns.
struct ThreadPool::Region {
    explicit Region(int threads) : chunks(threads), spans(std::size_t(threads)) {}
    ChunkClaims chunks;
    bool timed = false;  // this region's chunks are timed (published with the job)
    struct Span {
        Clock::time_point begin, end;
        bool ran = false;
    };
    std::vector<Span> spans;  // per chunk, read once every chunk is done

    // Runs chunks of the region until none is left to claim (each is claimed exactly once).
    void claim() {
        chunks.claim([this](int c, int begin, int end) {
            Span& span = spans[std::size_t(c)];
            if (timed) span.begin = Clock::now();
            (*chunks.job)(begin, end);
            if (timed) span.end = Clock::now(), span.ran = true;
        });
    }
};

ThreadPool::ThreadPool(int threads)
    : threads_(threads < 1 ? 1 : threads), region_(std::make_shared<Region>(threads_)) {}

ThreadPool::~ThreadPool() { stopWorkers(); }

void ThreadPool::useHost(TaskSystem* host) {
    if (host) stopWorkers();
    host_ = host;
}

void ThreadPool::startWorkers() {
    const unsigned seen = generation_.load(std::memory_order_acquire);
    for (int i = 1; i < threads_; ++i) workers_.emplace_back([this, seen] { worker(seen); });
}

void ThreadPool::stopWorkers() {
    if (workers_.empty()) return;
    stop_.store(true, std::memory_order_release);
    generation_.fetch_add(1, std::memory_order_acq_rel);
    generation_.notify_all();
    for (auto& t : workers_) t.join();
    workers_.clear();
    stop_.store(false, std::memory_order_release);
}

void ThreadPool::run(int n, const std::function<void(int, int)>& fn) {
    if (threads_ == 1 || n < 2 * threads_) {
        fn(0, n);
        return;
    }
    if (!host_ && workers_.empty()) startWorkers();
    Region& r = *region_;
    r.timed = bool(observer_);
    for (Region::Span& s : r.spans) s.ran = false;
    r.chunks.post(n, fn);  // publishes the job, n and the spans
    if (host_) {
        for (int c = 1; c < threads_; ++c) host_->enqueue([region = region_] { region->claim(); });
    } else {
        generation_.fetch_add(1, std::memory_order_acq_rel);
        generation_.notify_all();
    }
    r.claim();  // every chunk no worker or helper has started: a late one costs no wait
    for (int spins = 0; !r.chunks.finished(); ++spins)
        if (spins > 1000) std::this_thread::yield();
    if (r.timed)
        for (int c = 1; c < threads_; ++c)
            if (r.spans[std::size_t(c)].ran) observer_(c, r.spans[std::size_t(c)].begin, r.spans[std::size_t(c)].end);
}

void ThreadPool::worker(unsigned seen) {
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
        region_->claim();
    }
}

}  // namespace cloth
