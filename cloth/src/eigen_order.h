#pragma once
// Eigen's 3x3 products on packs (pack.h), with Eigen's own order of operations, so that a kernel
// that takes several blocks at once, a block per lane, keeps the bits of the Eigen loop it replaces.
// The order is Eigen's at the library's baseline (x86-64, SSE2: a packet holds two doubles) for
// Mat3 * Vec3: rows 0 and 1 as one packet, summed left to right; row 2 by a reduction that halves,
// m0 u0 + (m1 u1 + m2 u2). Eigen evaluates f * (M * u) as (f M) u.

#include <cstddef>
#include <type_traits>

#include "cloth/types.h"
#include "pack.h"

namespace cloth {

// Row r of M u, M's row given as its three entries (a lane per block).
template <class V>
CLOTH_INLINE inline V mat3Row(int r, const V& m0, const V& m1, const V& m2, const V* u) {
    return r < 2 ? m0 * u[0] + m1 * u[1] + m2 * u[2] : m0 * u[0] + (m1 * u[1] + m2 * u[2]);
}

// Row r of (f M) u, M by row-major entry arrays (M[e][b] for block b), blocks b.. in the lanes.
template <class V>
CLOTH_INLINE inline V scaledMat3Row(Scalar f, const Scalar* const* M, int r, const V* u, std::size_t b) {
    return mat3Row<V>(r, f * load<V>(M[3 * r] + b), f * load<V>(M[3 * r + 1] + b), f * load<V>(M[3 * r + 2] + b), u);
}

// The lanes of v into p[stride * (b + l) + offset].
template <class V>
CLOTH_INLINE inline void storeStrided(double* p, std::size_t b, int stride, int offset, const V& v) {
    if constexpr (std::is_same_v<V, double>) {
        p[stride * b + std::size_t(offset)] = v;
    } else {
        for (int l = 0; l < kLanes<double>; ++l) p[stride * (b + std::size_t(l)) + std::size_t(offset)] = v[l];
    }
}

}  // namespace cloth
