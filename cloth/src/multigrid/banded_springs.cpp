#include "banded_springs.h"

#include <mutex>
#include <utility>

#include "../kernels.h"
#include "block_kernels.h"

namespace cloth {

namespace {

template <class T>
struct BandSpringArgs {
    const double *x0, *x1, *x2, *v0, *v1, *v2;
    const T *k, *rest, *freeRow;
    T* o[6];    // the band's six arrays of W, at row 0
    T* copy;    // the band's blocks in BlockMatrix::blocks (6 per slot), or null where not kept
    T* bt[3];
    T* g[4];    // the band's compact arrays (BandedSprings::spring)
    int offset;
    T h, h2;
    bool compressionRule;
};

// Eqs. 15-17 for the slots [begin, end) of one band: W's block -h^2 J (zero where an end is pinned
// or there is no spring) into the band, BlockMatrix::blocks and the compact arrays, and the term
// of b for the lower end, h fm u + h^2 J (v_upper - v_lower) (the upper end's is the negative).
template <class T>
CLOTH_SIMD_CLONES void bandSpringKernel(const BandSpringArgs<T>& a, int begin, int end) {
    const int d = a.offset;
    const double *__restrict x0 = a.x0, *__restrict x1 = a.x1, *__restrict x2 = a.x2;
    const double *__restrict v0 = a.v0, *__restrict v1 = a.v1, *__restrict v2 = a.v2;
    const T *__restrict k = a.k, *__restrict rest = a.rest, *__restrict freeRow = a.freeRow;
    T *__restrict o0 = a.o[0], *__restrict o1 = a.o[1], *__restrict o2 = a.o[2];
    T *__restrict o3 = a.o[3], *__restrict o4 = a.o[4], *__restrict o5 = a.o[5];
    T *__restrict copy = a.copy, *__restrict b0 = a.bt[0], *__restrict b1 = a.bt[1], *__restrict b2 = a.bt[2];
    T *__restrict g0 = a.g[0], *__restrict g1 = a.g[1], *__restrict g2 = a.g[2], *__restrict gc = a.g[3];
    const T h = a.h, h2 = a.h2;
    const bool compressionRule = a.compressionRule;
CLOTH_IVDEP
    for (int p = begin; p < end; ++p) {
        const SpringTerms<T> t = springTerms(T(x0[p + d] - x0[p]), T(x1[p + d] - x1[p]), T(x2[p + d] - x2[p]), k[p],
                                             rest[p], compressionRule);
        T J[6];
        jacobianOf(t, J);
        const T J0 = J[0], J1 = J[1], J2 = J[2], J3 = J[3], J4 = J[4], J5 = J[5];
        const T mask = freeRow[p] * freeRow[p + d], scale = mask * -h2;
        o0[p] = scale * J0;
        o1[p] = scale * J1;
        o2[p] = scale * J2;
        o3[p] = scale * J3;
        o4[p] = scale * J4;
        o5[p] = scale * J5;
        const T gs = mask * h * std::sqrt(t.b);
        g0[p] = gs * t.ux;
        g1[p] = gs * t.uy;
        g2[p] = gs * t.uz;
        gc[p] = mask * h2 * t.a;
        const T q0 = T(v0[p + d] - v0[p]), q1 = T(v1[p + d] - v1[p]), q2 = T(v2[p + d] - v2[p]);
        b0[p] = h * t.fm * t.ux + h2 * (J0 * q0 + J1 * q1 + J2 * q2);
        b1[p] = h * t.fm * t.uy + h2 * (J1 * q0 + J3 * q1 + J4 * q2);
        b2[p] = h * t.fm * t.uz + h2 * (J2 * q0 + J4 * q1 + J5 * q2);
    }
    // The block copy in a loop of its own: interleaved stores in the loop above stop it vectorizing.
    if (!copy) return;
    for (int p = begin; p < end; ++p) {
        copy[6 * p] = o0[p], copy[6 * p + 1] = o1[p], copy[6 * p + 2] = o2[p];
        copy[6 * p + 3] = o3[p], copy[6 * p + 4] = o4[p], copy[6 * p + 5] = o5[p];
    }
}

// (y0, y1, y2) += O x for the spring blocks O = -(c I + g g^T) (BandedSprings::spring, at the
// rows) and x (three arrays, at the columns).
template <class T, class V>
CLOTH_INLINE inline void addSpringTimes(const T* g0, const T* g1, const T* g2, const T* c, const T* x0, const T* x1,
                                        const T* x2, V& y0, V& y1, V& y2) {
    const V G0 = load<V>(g0), G1 = load<V>(g1), G2 = load<V>(g2), C = load<V>(c);
    const V X0 = load<V>(x0), X1 = load<V>(x1), X2 = load<V>(x2);
    const V gx = G0 * X0 + G1 * X1 + G2 * X2;
    y0 -= C * X0 + gx * G0;
    y1 -= C * X1 + gx * G1;
    y2 -= C * X2 + gx * G2;
}

// Rows i... of b - W x (or W x): the diagonal blocks of W, then each band's springs from the
// row's lower and upper side, in that order for every row.
template <class T, class V>
CLOTH_INLINE inline void springBandLanes(const BlockMatrix<T>& W, const BandedSprings<T>& S, const T* X0, const T* X1,
                                         const T* X2, const T* b, T* out, int i) {
    V y0{}, y1{}, y2{};
    const std::size_t s = W.stride;
    const T* D = W.values.data() + W.pad;
    addBlockTimes(D + i, D + s + i, D + 2 * s + i, D + 3 * s + i, D + 4 * s + i, D + 5 * s + i, X0 + i, X1 + i, X2 + i,
                  y0, y1, y2);
    const int bands = int(S.offsets.size());
    for (int k = 0; k < bands; ++k) {
        const int o = S.offsets[k];
        for (const int side : {1, -1}) {
            const int row = i + (side > 0 ? 0 : -o), col = i + side * o;
            addSpringTimes(S.sp(k, 0) + row, S.sp(k, 1) + row, S.sp(k, 2) + row, S.sp(k, 3) + row, X0 + col, X1 + col,
                           X2 + col, y0, y1, y2);
        }
    }
    storeRows(y0, y1, y2, b ? b + 3 * std::size_t(i) : nullptr, out + 3 * std::size_t(i));
}

template <class T>
CLOTH_SIMD_CLONES void springBandRows(const BlockMatrix<T>& W, const BandedSprings<T>& S, const T* X0, const T* X1,
                                      const T* X2, const T* b, T* out, int begin, int end) {
    int i = begin;
    for (; i + kLanes<T> <= end; i += kLanes<T>) springBandLanes<T, Pack<T>>(W, S, X0, X1, X2, b, out, i);
    for (; i < end; ++i) springBandLanes<T, T>(W, S, X0, X1, X2, b, out, i);
}

// Rows [begin, end): D_i = base_i - sum over bands of (O_k[i] + O_k[i - o_k]) (from the blocks
// O = -h^2 J) into band 0, and the springs' part of b_i, sum over bands of (bt_k[i] - bt_k[i - o_k]),
// into b (3n).
template <class T>
CLOTH_SIMD_CLONES void bandRowSums(BlockMatrix<T>& A, const T* base, const BandedSprings<T>& S, T* b, int begin,
                                   int end) {
    alignas(64) T acc[9][kTile];
    const std::size_t st = A.stride;
    const int bands = int(A.offsets.size());
    T* V = A.values.data() + A.pad;
    for (int first = begin; first < end; first += kTile) {
        const int count = std::min(kTile, end - first);
        for (int t = 0; t < count; ++t) {
            for (int c = 0; c < 6; ++c) acc[c][t] = base[6 * std::size_t(first + t) + c];
            acc[6][t] = acc[7][t] = acc[8][t] = T(0);
        }
        for (int k = 1; k <= bands; ++k) {
            const int o = A.offsets[k - 1];
            for (const int row : {first, first - o}) {
                for (int c = 0; c < 6; ++c) {
                    const T* __restrict O = V + (6 * std::size_t(k) + c) * st + row;
                    T* __restrict y = acc[c];
CLOTH_IVDEP
                    for (int t = 0; t < count; ++t) y[t] -= O[t];
                }
                for (int c = 0; c < 3; ++c) {
                    const T* __restrict B = S.bt(k - 1, c) + row;
                    T* __restrict y = acc[6 + c];
                    if (row == first) {
CLOTH_IVDEP
                        for (int t = 0; t < count; ++t) y[t] += B[t];
                    } else {
CLOTH_IVDEP
                        for (int t = 0; t < count; ++t) y[t] -= B[t];
                    }
                }
            }
        }
        for (int c = 0; c < 6; ++c) std::copy(acc[c], acc[c] + count, V + c * st + first);
        for (int t = 0; t < count; ++t)
            for (int c = 0; c < 3; ++c) b[3 * std::size_t(first + t) + c] = acc[6 + c][t];
    }
}

// The state into the structure-of-arrays copies, and the free-row mask.
template <class T>
void loadState(BandedSprings<T>& B, const FineInputs<T>& in, ThreadPool& pool) {
    pool.run(B.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            for (int a = 0; a < 3; ++a) {
                B.xyz[a * B.len() + B.pad + i] = in.xs[3 * std::size_t(i) + a];
                B.vel[a * B.len() + B.pad + i] = in.vs[3 * std::size_t(i) + a];
            }
            B.freeRow[B.pad + i] = in.pinned[i] ? T(0) : T(1);
        }
    });
}

template <class T>
BandSpringArgs<T> bandArgs(BandedSprings<T>& B, const FineInputs<T>& in, BlockMatrix<T>& A, int k) {
    const int n = B.n;
    BandSpringArgs<T> a;
    a.x0 = B.x(0), a.x1 = B.x(1), a.x2 = B.x(2);
    a.v0 = B.v(0), a.v1 = B.v(1), a.v2 = B.v(2);
    a.k = &B.k[std::size_t(k) * n], a.rest = &B.rest[std::size_t(k) * n];
    a.freeRow = B.freeRow.data() + B.pad;
    for (int c = 0; c < 6; ++c) a.o[c] = A.bandArray(k + 1, c);
    a.copy = A.blocks.empty() ? nullptr : &A.blocks[6 * (std::size_t(n) + std::size_t(k) * n)];
    for (int c = 0; c < 3; ++c) a.bt[c] = B.bt(k, c);
    for (int q = 0; q < 4; ++q) a.g[q] = B.sp(k, q);
    a.offset = B.offsets[k];
    a.h = in.h, a.h2 = in.h2;
    a.compressionRule = in.compressionRule;
    return a;
}

// The springs and the row sums in one pass, tile by tile, so that the row sums read the blocks
// while they are in cache: row r sums slots r and r - o_k, so once a tile's slots are written, its
// rows are complete, except the first `reach` rows of a chunk after the first (their slots r - o_k
// belong to the chunk before), which are summed after the pass. Each row's sum is the same
// whoever computes it: the same bits for any thread count.
template <class T>
void springsAndRowSums(BandedSprings<T>& B, const FineInputs<T>& in, Level<T>& L, ThreadPool& pool) {
    const int n = B.n, bands = int(B.offsets.size());
    BandSpringArgs<T> args[BlockMatrix<T>::kMaxBands];
    for (int k = 0; k < bands; ++k) args[k] = bandArgs(B, in, L.A, k);
    const int reach = B.offsets.back();
    std::vector<std::pair<int, int>> seams;
    std::mutex seamsMutex;
    pool.run(n, [&](int begin, int end) {
        const int ready = begin == 0 ? 0 : std::min(end, begin + reach);
        for (int first = begin; first < end; first += kTile) {
            const int last = std::min(end, first + kTile);
            for (int k = 0; k < bands; ++k) bandSpringKernel<T>(args[k], first, last);
            const int from = std::max(first, ready);
            if (from < last) bandRowSums(L.A, in.base, B, L.b.data(), from, last);
        }
        if (ready > begin) {
            const std::lock_guard<std::mutex> lock(seamsMutex);
            seams.push_back({begin, ready});
        }
    });
    for (const auto& [from, to] : seams) bandRowSums(L.A, in.base, B, L.b.data(), from, to);
}

// For each spring with a pinned end (few; in a fixed order): h^2 J on the free end's diagonal and
// h^2 J dv_pinned in its b (the block itself is zero: the pinned particle is not an unknown).
template <class T>
void pinnedEnds(const BandedSprings<T>& B, const FineInputs<T>& in, Level<T>& L) {
    const int n = B.n, bands = int(B.offsets.size());
    T* D = L.A.bandArray(0, 0);
    const std::size_t st = L.A.stride;
    for (int p = 0; p < n; ++p) {
        if (!in.pinned[p]) continue;
        for (int k = 0; k < bands; ++k) {
            const int o = B.offsets[k];
            for (const int q : {p + o, p - o}) {
                const int lo = std::min(p, q);
                if (q < 0 || q >= n || in.pinned[q] || B.k[std::size_t(k) * n + lo] == T(0)) continue;
                const SpringTerms<T> t = springTerms(T(B.x(0)[lo + o] - B.x(0)[lo]), T(B.x(1)[lo + o] - B.x(1)[lo]),
                                                     T(B.x(2)[lo + o] - B.x(2)[lo]), B.k[std::size_t(k) * n + lo],
                                                     B.rest[std::size_t(k) * n + lo], in.compressionRule);
                T J[6];
                jacobianOf(t, J);
                for (int c = 0; c < 6; ++c) D[c * st + q] += in.h2 * J[c];
                T Jq[3];
                symmetricTimes(J, &in.pinDv[3 * std::size_t(p)], Jq);
                for (int a = 0; a < 3; ++a) L.b[3 * std::size_t(q) + a] += in.h2 * Jq[a];
            }
        }
    }
}

// Per row: the diagonal block (zero for a pinned particle), its inverse, the free-row flag, and
// the terms of b without springs.
template <class T>
void finishRows(const FineInputs<T>& in, Level<T>& L, ThreadPool& pool) {
    BlockMatrix<T>& A = L.A;
    const T* D = A.bandArray(0, 0);
    const std::size_t st = A.stride;
    pool.run(A.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            const bool free = !in.pinned[i];
            T Di[6];
            for (int c = 0; c < 6; ++c) Di[c] = free ? D[c * st + i] : T(0);
            A.put(i, Di);
            symmetricInverse(Di, &L.dinv[6 * std::size_t(i)]);
            L.active[i] = free ? T(1) : T(0);
            T* bi = &L.b[3 * std::size_t(i)];
            in.rows.add(i, bi);
            if (!free) bi[0] = bi[1] = bi[2] = T(0);
        }
    });
}

}  // namespace

template <class T>
bool BandedSprings<T>::assign(const Model& cloth, BlockMatrix<T>& A) {
    offsets = A.bandOffsets();
    if (!used()) return false;
    const int bands = int(offsets.size());
    auto bandOf = [this](int d) { return int(std::lower_bound(offsets.begin(), offsets.end(), d) - offsets.begin()); };
    n = A.n;
    pad = offsets.back();
    k.assign(std::size_t(bands) * n, T(0));
    rest.assign(std::size_t(bands) * n, T(0));
    for (const Spring& sp : cloth.springs()) {
        const int lo = int(std::min(sp.i, sp.j));
        const std::size_t at = std::size_t(bandOf(int(std::max(sp.i, sp.j)) - lo)) * n + lo;
        k[at] = T(sp.k), rest[at] = T(sp.rest);
    }
    A.numberSlotsByBand(offsets);
    xyz.assign(3 * len(), 0.0);
    vel.assign(3 * len(), 0.0);
    freeRow.assign(len(), T(0));
    btStride = spacedLength<T>(std::size_t(n + pad));
    bterm.assign(3 * std::size_t(bands) * btStride, T(0));
    springStride = spacedLength<T>(std::size_t(n + pad));
    spring.assign(4 * std::size_t(bands) * springStride, T(0));
    return true;
}

template <class T>
void assembleBanded(BandedSprings<T>& B, const FineInputs<T>& in, Level<T>& L, ThreadPool& pool) {
    loadState(B, in, pool);
    springsAndRowSums(B, in, L, pool);
    pinnedEnds(B, in, L);
    finishRows(in, L, pool);
}

template <class T>
void springBandProduct(const BlockMatrix<T>& W, const BandedSprings<T>& S, const T* X0, const T* X1, const T* X2,
                       const T* b, T* out, int begin, int end) {
    springBandRows(W, S, X0, X1, X2, b, out, begin, end);
}

template struct BandedSprings<float>;
template struct BandedSprings<double>;
template void assembleBanded(BandedSprings<float>&, const FineInputs<float>&, Level<float>&, ThreadPool&);
template void assembleBanded(BandedSprings<double>&, const FineInputs<double>&, Level<double>&, ThreadPool&);
template void springBandProduct(const BlockMatrix<float>&, const BandedSprings<float>&, const float*, const float*,
                                const float*, const float*, float*, int, int);
template void springBandProduct(const BlockMatrix<double>&, const BandedSprings<double>&, const double*, const double*,
                                const double*, const double*, double*, int, int);

}  // namespace cloth
