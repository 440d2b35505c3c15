#pragma once
// The inner steps that the banded products share (block_matrix.cpp, banded_springs.cpp), for the
// rows i... of one V: a pack of lanes (../pack.h) or, at a range's tail, one row (V = T). Always
// inlined, so that each runs in the SIMD clone of its caller; the sums stay in registers while a
// product walks its bands.

#include "../pack.h"

namespace cloth {

// (y0, y1, y2) += S x for the symmetric blocks S (six arrays, at the rows) and x (three arrays,
// at the columns).
template <class T, class V>
CLOTH_INLINE inline void addBlockTimes(const T* s0, const T* s1, const T* s2, const T* s3, const T* s4, const T* s5,
                                       const T* x0, const T* x1, const T* x2, V& y0, V& y1, V& y2) {
    const V S0 = load<V>(s0), S1 = load<V>(s1), S2 = load<V>(s2), S3 = load<V>(s3), S4 = load<V>(s4), S5 = load<V>(s5);
    const V X0 = load<V>(x0), X1 = load<V>(x1), X2 = load<V>(x2);
    y0 += S0 * X0 + S1 * X1 + S2 * X2;
    y1 += S1 * X0 + S3 * X1 + S4 * X2;
    y2 += S2 * X0 + S4 * X1 + S5 * X2;
}

// The rows' W x, in three V, into out (interleaved, at the first row): b - W x, or W x without b.
template <class T, class V>
CLOTH_INLINE inline void storeRows(const V& y0, const V& y1, const V& y2, const T* b, T* out) {
    constexpr int lanes = int(sizeof(V) / sizeof(T));
    T t0[lanes], t1[lanes], t2[lanes];
    store(t0, y0), store(t1, y1), store(t2, y2);
    if (b) {
        for (int l = 0; l < lanes; ++l)
            out[3 * l] = b[3 * l] - t0[l], out[3 * l + 1] = b[3 * l + 1] - t1[l], out[3 * l + 2] = b[3 * l + 2] - t2[l];
    } else {
        for (int l = 0; l < lanes; ++l) out[3 * l] = t0[l], out[3 * l + 1] = t1[l], out[3 * l + 2] = t2[l];
    }
}

}  // namespace cloth
