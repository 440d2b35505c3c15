#include "reductions.h"

#include <algorithm>

#include "../simd.h"

namespace cloth {

namespace {

// sum a_q b_q in double over eight lanes (q mod 8), added in a fixed order: the same bits on
// every CPU and clone, and no chain of dependent additions.
template <class T>
CLOTH_SIMD_CLONES double laneDot(const T* __restrict a, const T* __restrict b, std::size_t count) {
    constexpr std::size_t lanes = 8;
    double acc[lanes] = {0, 0, 0, 0, 0, 0, 0, 0};
    std::size_t q = 0;
    for (; q + lanes <= count; q += lanes)
        for (std::size_t k = 0; k < lanes; ++k) acc[k] += double(a[q + k]) * double(b[q + k]);
    for (std::size_t k = 0; q < count; ++q, ++k) acc[k] += double(a[q]) * double(b[q]);
    return ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
}

}  // namespace

template <class T>
double Reductions::dot(const std::vector<T>& a, const std::vector<T>& b) {
    const int n = int(a.size() / 3);
    partial_.assign(chunksOf(n), 0.0);
    pool_.run(chunksOf(n), [&](int begin, int end) {
        for (int ch = begin; ch < end; ++ch) {
            const std::size_t first = 3 * std::size_t(ch) * kChunk;
            const std::size_t last = std::min(a.size(), 3 * std::size_t(ch + 1) * kChunk);
            partial_[ch] = laneDot(a.data() + first, b.data() + first, last - first);
        }
    });
    double s = 0;
    for (double p : partial_) s += p;
    return s;
}

template double Reductions::dot(const std::vector<float>&, const std::vector<float>&);
template double Reductions::dot(const std::vector<double>&, const std::vector<double>&);

}  // namespace cloth
