#include "nested_galerkin.h"

#include <cstdlib>
#include <utility>

#include "../simd.h"

namespace cloth {

namespace {

using Offsets2d = std::vector<std::pair<int, int>>;
using BandGrid = int[5][5];  // the band of each 2D offset (dx, dy), |dx|, |dy| <= 2, at [dy + 2][dx + 2]; -1: none

// The coarse offsets D that the terms fill: the diagonal, then the upper half of |D| <= 2.
Offsets2d nestedOffsets() {
    Offsets2d d = {{0, 0}, {1, 0}, {2, 0}};
    for (int dy = 1; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) d.push_back({dx, dy});
    return d;
}

// One row of output blocks, the sum of the terms: band d's six numbers of output point X at
// out[d][q * outStride + X] (out[d] null: no such band, and its terms are skipped). V: the source
// level's banded values, band k's six arrays from V + bandAt[k], `stride` apart; a term reads the
// source row rowScale * Y + a_y (of `rows`, `pitch` apart), every Step-th point from 2 X + a_x
// (Step 2: a fine row coarsened in x) or X (Step 1).
template <class T, int Step>
CLOTH_SIMD_CLONES void nestedGalerkinRow(const NestedTerm<T>* terms, int count, const T* V, const std::size_t* bandAt,
                                         std::size_t stride, int pitch, int rows, int rowScale, int cx, int Y,
                                         T* const* out, std::size_t outStride, int bands) {
    bool written[BlockMatrix<T>::kMaxBands + 1] = {};
    for (int t = 0; t < count; ++t) {
        const NestedTerm<T>& term = terms[t];
        const int fy = rowScale * Y + term.ay;
        if (fy < 0 || fy >= rows || !out[term.dst]) continue;
        const int x0 = term.ax < 0 ? 1 : 0, x1 = term.ax > 0 ? cx - 1 : cx;  // fine point 2X + a_x on the grid
        const std::ptrdiff_t first =
            std::ptrdiff_t(bandAt[term.band]) + std::ptrdiff_t(fy) * pitch + term.ax + term.shift;
        const T w = term.w;
        const std::ptrdiff_t st = std::ptrdiff_t(stride);
        const T *__restrict s0 = V + first, *__restrict s1 = s0 + st, *__restrict s2 = s1 + st;
        const T *__restrict s3 = s2 + st, *__restrict s4 = s3 + st, *__restrict s5 = s4 + st;
        T *__restrict g0 = out[term.dst], *__restrict g1 = g0 + outStride, *__restrict g2 = g1 + outStride;
        T *__restrict g3 = g2 + outStride, *__restrict g4 = g3 + outStride, *__restrict g5 = g4 + outStride;
        if (written[term.dst]) {
            CLOTH_IVDEP
            for (int X = x0; X < x1; ++X) {
                g0[X] += w * s0[Step * X], g1[X] += w * s1[Step * X], g2[X] += w * s2[Step * X];
                g3[X] += w * s3[Step * X], g4[X] += w * s4[Step * X], g5[X] += w * s5[Step * X];
            }
            continue;
        }
        // A band's first term sets its row (0 + a and a are the same number, so the sums keep
        // their bits).
        written[term.dst] = true;
        for (T* g : {g0, g1, g2, g3, g4, g5}) std::fill(g, g + x0, T(0)), std::fill(g + x1, g + cx, T(0));
        CLOTH_IVDEP
        for (int X = x0; X < x1; ++X) {
            g0[X] = w * s0[Step * X], g1[X] = w * s1[Step * X], g2[X] = w * s2[Step * X];
            g3[X] = w * s3[Step * X], g4[X] = w * s4[Step * X], g5[X] = w * s5[Step * X];
        }
    }
    for (int d = 0; d < bands; ++d)  // a band no term reaches in this row
        for (int q = 0; out[d] && !written[d] && q < 6; ++q) std::fill_n(out[d] + q * outStride, cx, T(0));
}

// The fine bands as 2D offsets; false if a band is not within 2 points.
bool fineBands(const std::vector<int>& offsets, int nx, BandGrid& bandOf) {
    for (auto& row : bandOf) std::fill(row, row + 5, -1);
    bandOf[2][2] = 0;
    for (std::size_t k = 0; k < offsets.size(); ++k) {
        const int o = offsets[k], dy = (o + 2) / nx, dx = o - dy * nx;
        if (dy > 2 || dx < -2 || dx > 2) return false;
        bandOf[dy + 2][dx + 2] = int(k) + 1;
        bandOf[2 - dy][2 - dx] = int(k) + 1;
    }
    return true;
}

// The intermediate grid's offsets (Dx, dy), upper half: a fine pair (2X + a, 2(X + Dx) + b) in x,
// the fine offset in y; halfOf gets the band of each offset (either orientation; -1: none).
Offsets2d halfOffsets(const BandGrid& bandOf, BandGrid& halfOf) {
    Offsets2d half = {{0, 0}};
    for (auto& row : halfOf) std::fill(row, row + 5, -1);
    halfOf[2][2] = 0;
    for (int fy = -2; fy <= 2; ++fy)
        for (int fx = -2; fx <= 2; ++fx)
            for (int a = -1; a <= 1; ++a)
                for (int b = -1; b <= 1; ++b) {
                    if (bandOf[fy + 2][fx + 2] < 0 || (fx + a - b) % 2 != 0) continue;
                    int Dx = (fx + a - b) / 2, dy = fy;
                    if (dy < 0 || (dy == 0 && Dx < 0)) Dx = -Dx, dy = -dy;
                    if (halfOf[dy + 2][Dx + 2] >= 0) continue;
                    halfOf[dy + 2][Dx + 2] = halfOf[2 - dy][2 - Dx] = int(half.size());
                    half.push_back({Dx, dy});
                }
    return half;
}

// One dimension's terms: output offset o = (ox, oy) gets, for a, b in {-1, 0, 1}, the source band
// of the offset with 2 o + b - a along the dimension coarsened and o along the other.
// x: T((X, y), (X + Dx, y + dy)) = sum over a, b of w_a w_b W((2X + a, y), (2X + 2Dx + b, y + dy));
// y: W_c((X, Y), (X + Dx, Y + Dy)) = sum over a, b of w_a w_b T((X, 2Y + a), (X + Dx, 2Y + 2Dy + b)).
template <class T>
std::vector<NestedTerm<T>> termsOf(const Offsets2d& outs, const BandGrid& source, bool alongX, int pitch) {
    auto weight = [](int a) { return a == 0 ? 1.0 : 0.5; };  // bilinear P, one dimension
    std::vector<NestedTerm<T>> terms;
    for (std::size_t d = 0; d < outs.size(); ++d)
        for (int a = -1; a <= 1; ++a)
            for (int b = -1; b <= 1; ++b) {
                int sx = outs[d].first, sy = outs[d].second;
                int& along = alongX ? sx : sy;
                along = 2 * along + b - a;
                if (std::abs(sx) > 2 || std::abs(sy) > 2 || source[sy + 2][sx + 2] < 0) continue;
                NestedTerm<T> t;
                t.dst = int(d);
                t.band = source[sy + 2][sx + 2];
                (alongX ? t.ax : t.ay) = a;
                t.shift = std::min(sy * pitch + sx, 0);
                t.w = T(weight(a) * weight(b));
                terms.push_back(t);
            }
    return terms;
}

// Where each (coarse band, row) goes; false unless every entry of the coarse pattern is one of them.
template <class T>
bool coarseDestinations(const BlockMatrix<T>& coarse, const Offsets2d& D, int cx, int cy, std::vector<int>& dst) {
    const int nc = cx * cy;
    dst.assign(D.size() * nc, -1);
    int reached = 0;
    for (int I = 0; I < nc; ++I) {
        const int X = I % cx, Y = I / cx;
        dst[I] = I;
        for (std::size_t d = 1; d < D.size(); ++d) {
            const int JX = X + D[d].first, JY = Y + D[d].second;
            if (JX < 0 || JX >= cx || JY >= cy) continue;
            const int e = coarse.entryOf(I, JY * cx + JX);
            if (e < 0) continue;
            dst[d * nc + I] = nc + coarse.slot[e];
            ++reached;
        }
    }
    return 2 * reached == coarse.entries();
}

}  // namespace

template <class T>
bool NestedGalerkin<T>::build(const BlockMatrix<T>& fine, const BlockMatrix<T>& coarse, int nx, int ny, int minRow) {
    if (nx % 2 == 0 || ny % 2 == 0 || nx < 5 || ny < 5 || (nx + 1) / 2 < minRow) return false;
    const std::vector<int> offsets = fine.bandOffsets();  // what layout() will choose
    BandGrid bandOf, halfOf;
    if (offsets.empty() || !fineBands(offsets, nx, bandOf)) return false;
    const Offsets2d D = nestedOffsets(), halfOffs = halfOffsets(bandOf, halfOf);
    const int cx = (nx + 1) / 2, cy = (ny + 1) / 2;
    std::vector<NestedTerm<T>> termsX = termsOf<T>(halfOffs, bandOf, true, nx), termsY = termsOf<T>(D, halfOf, false, cx);
    std::vector<int> where;
    if (!coarseDestinations(coarse, D, cx, cy, where)) return false;
    x = std::move(termsX);
    y = std::move(termsY);
    halfBands = int(halfOffs.size());
    halfPad = 2 * cx + 2;  // the most negative shift of a term of y
    halfStride = spacedLength<T>(std::size_t(cx) * ny + 2 * std::size_t(halfPad));
    half.assign(6 * std::size_t(halfBands) * halfStride, T(0));
    dst = std::move(where);
    gridNx = nx, gridNy = ny;
    return true;
}

namespace {

// The x pass: every fine row into the intermediate grid (its pad stays zero).
template <class T>
void coarsenRows(const NestedGalerkin<T>& G, const BlockMatrix<T>& W, T* half, const std::size_t* halfAt,
                 ThreadPool& pool) {
    const int nx = G.gridNx, ny = G.gridNy, cx = (nx + 1) / 2;
    std::size_t bandAt[BlockMatrix<T>::kMaxBands + 1];
    for (std::size_t k = 0; k <= W.offsets.size(); ++k) bandAt[k] = 6 * k * W.stride + W.pad;
    pool.run(ny, [&](int begin, int end) {
        T* out[BlockMatrix<T>::kMaxBands + 1];
        for (int y = begin; y < end; ++y) {
            for (int e = 0; e < G.halfBands; ++e) out[e] = half + halfAt[e] + y * cx;
            nestedGalerkinRow<T, 2>(G.x.data(), int(G.x.size()), W.values.data(), bandAt, W.stride, nx, ny, 1, cx, y,
                                    out, G.halfStride, G.halfBands);
        }
    });
}

// Band d of the terms is band bandC[d] of C (-1: no such band; then no pair of the pattern has
// that offset, and where a band's pair is off the grid, the terms sum to zero, as the band holds).
template <class T>
void coarseBands(const BlockMatrix<T>& C, int cx, int bandC[32]) {
    const Offsets2d D = nestedOffsets();
    for (int d = 0; d < int(D.size()); ++d) {
        const int o = D[d].second * cx + D[d].first;
        const auto it = std::lower_bound(C.offsets.begin(), C.offsets.end(), o);
        bandC[d] = d == 0 ? 0 : it != C.offsets.end() && *it == o ? 1 + int(it - C.offsets.begin()) : -1;
    }
}

// The y pass, row by coarse row. A banded coarse level gets its rows in place; its block copy,
// where a plan reads it, from there. A gathered coarse level gets its rows through G and put().
template <class T>
void coarsenColumns(const NestedGalerkin<T>& G, BlockMatrix<T>& C, const T* half, const std::size_t* halfAt,
                    ThreadPool& pool) {
    const int ny = G.gridNy, cx = (G.gridNx + 1) / 2, cy = (ny + 1) / 2, nc = C.n;
    const int bands = int(nestedOffsets().size());
    int bandC[32];
    coarseBands(C, cx, bandC);
    const bool direct = C.banded();
    pool.run(cy, [&](int begin, int end) {
        std::vector<T> rowsOut(direct ? 0 : std::size_t(bands) * 6 * cx);
        T* out[32];
        const std::size_t outStride = direct ? C.stride : std::size_t(cx);
        for (int Y = begin; Y < end; ++Y) {
            for (int d = 0; d < bands; ++d)
                out[d] = !direct ? &rowsOut[std::size_t(d) * 6 * cx]
                         : bandC[d] >= 0 ? &C.values[6 * std::size_t(bandC[d]) * C.stride + C.pad + Y * cx]
                                         : nullptr;
            nestedGalerkinRow<T, 1>(G.y.data(), int(G.y.size()), half, halfAt, G.halfStride, cx, ny, 2, cx, Y, out,
                                    outStride, bands);
            if (direct && C.blocks.empty()) continue;  // nothing else holds the blocks
            for (int d = 0; d < bands; ++d)
                for (int X = 0; out[d] && X < cx; ++X) {
                    const int to = G.dst[std::size_t(d) * nc + Y * cx + X];
                    if (to < 0) continue;
                    T block[6];
                    for (int q = 0; q < 6; ++q) block[q] = out[d][q * outStride + X];
                    if (direct) std::copy(block, block + 6, &C.blocks[6 * std::size_t(to)]);
                    else C.put(to, block);
                }
        }
    });
}

}  // namespace

template <class T>
void NestedGalerkin<T>::apply(const BlockMatrix<T>& fine, BlockMatrix<T>& coarse, ThreadPool& pool) {
    std::size_t halfAt[BlockMatrix<T>::kMaxBands + 1];  // band e's first array in `half`
    for (int e = 0; e < halfBands; ++e) halfAt[e] = 6 * std::size_t(e) * halfStride + halfPad;
    coarsenRows(*this, fine, half.data(), halfAt, pool);
    coarsenColumns(*this, coarse, half.data(), halfAt, pool);
}

template struct NestedGalerkin<float>;
template struct NestedGalerkin<double>;

}  // namespace cloth
