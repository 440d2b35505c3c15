#pragma once
// Sums over rows that give the same bits for any thread count: rows in chunks of kChunk, each
// chunk summed in a fixed order over eight lanes, the chunks added in order.

#include <cmath>
#include <vector>

#include "cloth/thread_pool.h"

namespace cloth {

constexpr int kChunk = 256;
inline int chunksOf(int n) { return (n + kChunk - 1) / kChunk; }

class Reductions {
public:
    explicit Reductions(ThreadPool& pool) : pool_(pool) {}
    // a . b in double, for vectors of 3 numbers a row.
    template <class T>
    double dot(const std::vector<T>& a, const std::vector<T>& b);
    template <class T>
    double norm(const std::vector<T>& v) {
        return std::sqrt(dot(v, v));
    }
    ThreadPool& pool() { return pool_; }
    // Scratch for a caller's own per-chunk partial results.
    std::vector<double>& partial() { return partial_; }

private:
    ThreadPool& pool_;
    std::vector<double> partial_;
};

}  // namespace cloth
