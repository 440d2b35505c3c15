#pragma once
// The inner loops that the banded products share (block_matrix.cpp, banded_springs.cpp): always
// inlined, so that each runs in the SIMD clone of its caller.

#include "../simd.h"

namespace cloth {

// y (tile of rows) += S x for the symmetric blocks S (six arrays) and x (three arrays).
template <class T>
CLOTH_INLINE inline void addBlockTimes(const T* __restrict s0, const T* __restrict s1, const T* __restrict s2,
                                       const T* __restrict s3, const T* __restrict s4, const T* __restrict s5,
                                       const T* __restrict x0, const T* __restrict x1, const T* __restrict x2,
                                       int count, T* __restrict y0, T* __restrict y1, T* __restrict y2) {
CLOTH_IVDEP
    for (int t = 0; t < count; ++t) {
        y0[t] += s0[t] * x0[t] + s1[t] * x1[t] + s2[t] * x2[t];
        y1[t] += s1[t] * x0[t] + s3[t] * x1[t] + s4[t] * x2[t];
        y2[t] += s2[t] * x0[t] + s4[t] * x1[t] + s5[t] * x2[t];
    }
}

// A tile of a product's rows, W x in three arrays, into out (interleaved): b - W x, or W x
// without b.
template <class T>
CLOTH_INLINE inline void storeTile(const T* y0, const T* y1, const T* y2, int count, const T* b, T* out) {
    if (b) {
        for (int t = 0; t < count; ++t)
            out[3 * t] = b[3 * t] - y0[t], out[3 * t + 1] = b[3 * t + 1] - y1[t], out[3 * t + 2] = b[3 * t + 2] - y2[t];
    } else {
        for (int t = 0; t < count; ++t) out[3 * t] = y0[t], out[3 * t + 1] = y1[t], out[3 * t + 2] = y2[t];
    }
}

}  // namespace cloth
