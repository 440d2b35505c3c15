#include "multigrid.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <sstream>
#include <type_traits>

#include "kernels.h"
#include "simd.h"

namespace cloth {

namespace {

// Sums over rows run in chunks of this many rows, each chunk summed in order, chunks added in
// order: the same bits for any thread count.
constexpr int kChunk = 256;

// P: fine rows -> coarse columns, kept both ways (prolongation by fine row, restriction by coarse
// row), so both are gathers that split across threads.
struct Transfer {
    int fine = 0, coarse = 0;
    std::vector<int> pStart, pCol, rStart, rRow;
    std::vector<double> pW, rW;
    std::string label;  // "17x17" or "aggregates 123"

    static Transfer fromSparse(const Eigen::SparseMatrix<double, Eigen::RowMajor>& P) {
        Transfer t;
        t.fine = int(P.rows());
        t.coarse = int(P.cols());
        auto fill = [](const auto& M, std::vector<int>& start, std::vector<int>& idx, std::vector<double>& w) {
            start.assign(1, 0);
            for (int r = 0; r < M.outerSize(); ++r) {
                for (typename std::decay_t<decltype(M)>::InnerIterator it(M, r); it; ++it)
                    if (it.value() != 0) idx.push_back(int(it.col())), w.push_back(it.value());
                start.push_back(int(idx.size()));
            }
        };
        fill(P, t.pStart, t.pCol, t.pW);
        const Eigen::SparseMatrix<double, Eigen::RowMajor> R = P.transpose();
        fill(R, t.rStart, t.rRow, t.rW);
        return t;
    }

    // acc = sum over row I of P (prolong = true: fine row, coarse columns) or of P^T (restrict:
    // coarse row, fine columns) of w * src[3 col .. 3 col + 2].
    template <class A, class S>
    void gather(bool prolong, int row, const S* src, A acc[3]) const {
        const std::vector<int>& start = prolong ? pStart : rStart;
        const std::vector<int>& col = prolong ? pCol : rRow;
        const std::vector<double>& w = prolong ? pW : rW;
        acc[0] = acc[1] = acc[2] = A(0);
        for (int e = start[row]; e < start[row + 1]; ++e) {
            const A we = A(w[e]);
            const S* v = &src[3 * std::size_t(col[e])];
            acc[0] += we * v[0], acc[1] += we * v[1], acc[2] += we * v[2];
        }
    }
};

// Linear interpolation from nc points to nf points over the same interval.
std::vector<std::vector<std::pair<int, double>>> interpolation1d(int nf, int nc) {
    std::vector<std::vector<std::pair<int, double>>> rows(nf);
    for (int c = 0; c < nf; ++c) {
        if (nc == nf) {
            rows[c] = {{c, 1.0}};
            continue;
        }
        const double t = double(c) * (nc - 1) / (nf - 1);
        const int c0 = std::min(int(std::floor(t)), nc - 2);
        const double fr = t - c0;
        if (1 - fr > 1e-12) rows[c].push_back({c0, 1 - fr});
        if (fr > 1e-12) rows[c].push_back({c0 + 1, fr});
    }
    return rows;
}

int coarserSide(int n) { return n <= 2 ? n : n / 2 + 1; }

Transfer gridTransfer(int nx, int ny, int cx, int cy) {
    const auto px = interpolation1d(nx, cx), py = interpolation1d(ny, cy);
    std::vector<Eigen::Triplet<double>> t;
    for (int r = 0; r < ny; ++r)
        for (int c = 0; c < nx; ++c)
            for (const auto& [R, wr] : py[r])
                for (const auto& [C, wc] : px[c]) t.emplace_back(r * nx + c, R * cx + C, wr * wc);
    Eigen::SparseMatrix<double, Eigen::RowMajor> P(nx * ny, cx * cy);
    P.setFromTriplets(t.begin(), t.end());
    Transfer tr = Transfer::fromSparse(P);
    tr.label = std::to_string(cx) + "x" + std::to_string(cy);
    return tr;
}

// Smoothed aggregation from a scalar stiffness Laplacian L (zero row sums). Strong connections:
// -L_ij >= 0.25 max_k -L_ik (on a cloth mesh: edges, not the weaker bend springs).
Transfer aggregationTransfer(const Eigen::SparseMatrix<double, Eigen::RowMajor>& L) {
    const int n = int(L.rows());
    std::vector<std::vector<std::pair<int, double>>> strong(n);
    for (int i = 0; i < n; ++i) {
        double maxOff = 0;
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(L, i); it; ++it)
            if (it.col() != i) maxOff = std::max(maxOff, -it.value());
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(L, i); it; ++it)
            if (it.col() != i && -it.value() >= 0.25 * maxOff && -it.value() > 0)
                strong[i].push_back({int(it.col()), -it.value()});
    }
    std::vector<int> agg(n, -1);
    int count = 0;
    for (int i = 0; i < n; ++i) {  // 1: a point whose strong neighbours are all free, with them
        if (agg[i] >= 0) continue;
        bool free = true;
        for (const auto& [j, w] : strong[i]) free = free && agg[j] < 0;
        if (!free) continue;
        agg[i] = count;
        for (const auto& [j, w] : strong[i]) agg[j] = count;
        ++count;
    }
    std::vector<int> joined = agg;
    for (int i = 0; i < n; ++i) {  // 2: the rest join their strongest aggregated neighbour
        if (agg[i] >= 0) continue;
        double best = 0;
        for (const auto& [j, w] : strong[i])
            if (agg[j] >= 0 && w > best) best = w, joined[i] = agg[j];
    }
    for (int i = 0; i < n; ++i)  // 3: isolated points are aggregates of their own
        if (joined[i] < 0) joined[i] = count++;
    // P = (I - omega D^-1 Lf) P_tent, Lf: the strong part of L with zero row sums, omega =
    // 4 / (3 rho), rho the spectral radius of D^-1 Lf (by power iteration; at most 2).
    std::vector<double> diag(n, 0.0);
    for (int i = 0; i < n; ++i)
        for (const auto& [j, w] : strong[i]) diag[i] += w;
    double rho = 2;
    {
        Eigen::VectorXd x(n), y(n);
        for (int i = 0; i < n; ++i) x[i] = (i % 2 ? 1.0 : -1.0) + 0.1 * std::sin(double(i));
        for (int it = 0; it < 30; ++it) {
            for (int i = 0; i < n; ++i) {
                double s = diag[i] * x[i];
                for (const auto& [j, w] : strong[i]) s -= w * x[j];
                y[i] = diag[i] > 0 ? s / diag[i] : 0.0;
            }
            rho = y.norm() / std::max(x.norm(), 1e-300);
            x = y / std::max(y.norm(), 1e-300);
        }
        rho = std::clamp(rho, 1.0, 2.0);
    }
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
        const double d = diag[i];
        if (d == 0) {
            t.emplace_back(i, joined[i], 1.0);
            continue;
        }
        const double s = 4.0 / (3.0 * rho) / d;
        t.emplace_back(i, joined[i], 1.0 - s * d);
        for (const auto& [j, w] : strong[i]) t.emplace_back(i, joined[j], s * w);
    }
    Eigen::SparseMatrix<double, Eigen::RowMajor> P(n, count);
    P.setFromTriplets(t.begin(), t.end());
    P.prune(1e-14, 1);
    Transfer tr = Transfer::fromSparse(P);
    tr.label = std::to_string(count);
    return tr;
}

// sum a_q b_q in double over eight lanes (q mod 8), added in a fixed order: the same bits on
// every CPU and clone, and no chain of dependent additions (one chain made the dots of an adaptive
// float solve at 129x129 10% of its time).
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

// out += w s for a block s (six numbers).
template <class T>
void symAxpy(T w, const T* s, T* out) {
    for (int k = 0; k < 6; ++k) out[k] += w * s[k];
}

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

// out = b - W x (b given) or W x, rows [begin, end), for a banded W; x as three arrays X0, X1, X2
// with W.pad zeros before and after.
template <class T>
CLOTH_SIMD_CLONES void bandedProduct(const BlockMatrix<T>& W, const T* X0, const T* X1, const T* X2, const T* b,
                                     T* out, int begin, int end) {
    alignas(64) T y0[kTile], y1[kTile], y2[kTile];
    const std::size_t s = W.stride;
    const int bands = int(W.offsets.size());
    for (int first = begin; first < end; first += kTile) {
        const int count = std::min(kTile, end - first);
        std::fill(y0, y0 + count, T(0)), std::fill(y1, y1 + count, T(0)), std::fill(y2, y2 + count, T(0));
        for (int k = 0; k <= bands; ++k) {
            const T* B = W.values.data() + 6 * std::size_t(k) * s + W.pad;
            for (const int side : {1, -1}) {
                if (k == 0 && side < 0) break;
                const int o = k == 0 ? 0 : W.offsets[k - 1];
                const int row = first + (side > 0 ? 0 : -o), col = first + side * o;
                addBlockTimes(B + row, B + s + row, B + 2 * s + row, B + 3 * s + row, B + 4 * s + row,
                              B + 5 * s + row, X0 + col, X1 + col, X2 + col, count, y0, y1, y2);
            }
        }
        storeTile(y0, y1, y2, count, b ? b + 3 * std::size_t(first) : nullptr, out + 3 * std::size_t(first));
    }
}

// The Galerkin product on nested grids. When both sides of a grid level are odd, its coarser grid
// keeps every other point (fine point 2I is coarse point I) and P is the same bilinear stencil
// everywhere, a product of one-dimensional ones (weights 1 and 1/2): P = P_y P_x. So the product
// runs one dimension at a time: T = P_x^T W P_x on an intermediate grid (cx x ny: the rows
// coarsened in x), then W_c = P_y^T T P_y. In each, a block of the output is
// sum over a, b in {-1,0,1} of w_a w_b (source block of the pair (2I + a, 2I + 2D + b) along that
// dimension), and each (D, a, b) whose source offset is a band is one term: the same band,
// shifted, for every output row. A row of output blocks is a fixed list of terms, each a stream
// down a source band, with no plan to read. Terms only for the upper half (and D = 0): T and W_c
// are symmetric. (By dimension, a 9-point level takes 23 + 2 x 23 terms per coarse point instead
// of 109 at once; perf, one double cycle at 129x129: 17% of the step instead of 22%.)
template <class T>
struct NestedTerm {
    int dst = 0;    // output band (0: the diagonal): the intermediate grid's, or nestedOffsets()' order
    int band = 0;   // source band holding W(i, i + o) (0: the diagonal)
    int ax = 0, ay = 0;
    int shift = 0;  // the block's source row: i (o in the upper half) or i + o (lower half: W_ji = W_ij)
    T w = 0;
};

// The coarse offsets D that the terms fill: the diagonal, then the upper half of |D| <= 2.
std::vector<std::pair<int, int>> nestedOffsets() {
    std::vector<std::pair<int, int>> d = {{0, 0}, {1, 0}, {2, 0}};
    for (int dy = 1; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) d.push_back({dx, dy});
    return d;
}

// One row of output blocks, the sum of the terms: band d's six numbers of output point X at
// out[d][q * outStride + X] (out[d] null: no such band, and its terms are skipped). V: the source
// level's banded values, band k's six arrays from V + bandAt[k], `stride` apart; a term reads the
// source row rowScale * Y + a_y (of `rows`, `pitch` apart), every Step-th point from 2 X + a_x
// (Step 2: a fine row coarsened in x) or X (Step 1). (Summing each band's terms in registers over
// chunks of points, instead of adding term by term into `out`, measured slower: GCC vectorized that
// loop only in part.)
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
        // their bits; zeroing every row first and adding was 5% of a one-cycle step at 129x129).
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

}  // namespace

// Array lengths in the banded layout are rounded to whole 4 KiB pages plus one cache line, so that
// the arrays a product streams through start in different cache sets (a whole number of pages
// apart, the 42 arrays of level 0 compete for a few sets and evict each other: a 1.5x slower step).
template <class T>
std::size_t spacedLength(std::size_t len) {
    constexpr std::size_t page = 4096 / sizeof(T), line = 64 / sizeof(T);
    return (len + page - 1) / page * page + line;
}

template <class T>
std::vector<int> BlockMatrix<T>::bandOffsets() const {
    // Banded needs one entry per (row, column): two springs between the same particles (a mesh
    // may have them) would share a band position.
    std::vector<int> all, row;
    for (int i = 0; i < n; ++i) {
        row.assign(col.begin() + start[i], col.begin() + start[i + 1]);
        std::sort(row.begin(), row.end());
        if (std::adjacent_find(row.begin(), row.end()) != row.end()) return {};
        for (int j : row)
            if (j > i) all.push_back(j - i);
    }
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    if (int(all.size()) > kMaxBands || n < 64) return {};
    return all;
}

template <class T>
void BlockMatrix<T>::layout(bool allowBands, bool keepBlocks) {
    offsets = allowBands ? bandOffsets() : std::vector<int>{};
    pad = 0;
    at.assign(std::size_t(n + slots), 0);
    if (offsets.empty()) {
        stride = 1;
        for (int b = 0; b < n + slots; ++b) at[b] = 6 * std::size_t(b);
        values.assign(6 * std::size_t(n + slots), T(0));
        blocks.clear();
        return;
    }
    pad = offsets.back();
    stride = spacedLength<T>(std::size_t(n + pad));
    for (int i = 0; i < n; ++i) {
        at[i] = pad + i;
        for (int e = start[i]; e < start[i + 1]; ++e)
            if (col[e] > i) {
                const int k = 1 + int(std::lower_bound(offsets.begin(), offsets.end(), col[e] - i) - offsets.begin());
                at[n + slot[e]] = 6 * std::size_t(k) * stride + pad + i;
            }
    }
    values.assign(6 * (offsets.size() + 1) * stride, T(0));
    if (keepBlocks) blocks.assign(6 * std::size_t(n + slots), T(0));
    else blocks.clear();
}

template <class T>
void BlockMatrix<T>::numberSlots() {
    slots = 0;
    slot.assign(entries(), -1);
    for (int i = 0; i < n; ++i)
        for (int e = start[i]; e < start[i + 1]; ++e)
            if (col[e] > i) slot[e] = slots++;
    for (int i = 0; i < n; ++i)
        for (int e = start[i]; e < start[i + 1]; ++e)
            if (col[e] < i) slot[e] = slot[entryOf(col[e], i)];
}

template <class T>
void BlockMatrix<T>::numberSlotsByBand(const std::vector<int>& bandOffsets) {
    slot.assign(entries(), -1);
    for (int i = 0; i < n; ++i)
        for (int e = start[i]; e < start[i + 1]; ++e) {
            const int d = std::abs(col[e] - i);
            const int k = int(std::lower_bound(bandOffsets.begin(), bandOffsets.end(), d) - bandOffsets.begin());
            slot[e] = k * n + std::min(i, col[e]);
        }
    slots = int(bandOffsets.size()) * n;
}

template <class T>
void BlockMatrix<T>::copyBandsToBlocks(int begin, int end) {
    for (std::size_t k = 0; k <= offsets.size(); ++k) {
        const T* band = values.data() + 6 * k * stride + pad;
        T* copy = blocks.data() + 6 * (k == 0 ? 0 : std::size_t(n) * k);  // diagonal, then slot (k - 1) n + i
        for (int i = begin; i < end; ++i)
            for (int q = 0; q < 6; ++q) copy[6 * std::size_t(i) + q] = band[q * stride + i];
    }
}

template <class T>
Eigen::MatrixXd BlockMatrix<T>::dense() const {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    auto put = [&](int i, int j, int b) {
        const int idx[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) M(3 * i + r, 3 * j + c) += double(get(b, idx[r][c]));
    };
    for (int i = 0; i < n; ++i) {
        put(i, i, i);
        for (int e = start[i]; e < start[i + 1]; ++e) put(i, col[e], n + slot[e]);
    }
    return M;
}

namespace {

// The springs of one level's cloth (level 0: the model; re-discretized coarse levels: the same
// cloth on a coarser grid), with their per-step terms (kernels.h).
template <class T>
struct SpringSet {
    std::vector<int> si, sj, adjSpring;
    std::vector<T> k, rest, adjSign;  // adjSign: +1 where the row is the spring's i end
    std::vector<T> bterm;
    std::vector<T> pinnedJ;  // 6 per spring, written only for a spring with a pinned end

    void assign(const Model& m) {
        const auto& springs = m.springs();
        const int S = m.springCount();
        si.resize(S), sj.resize(S), k.resize(S), rest.resize(S);
        for (int s = 0; s < S; ++s)
            si[s] = springs[s].i, sj[s] = springs[s].j, k[s] = T(springs[s].k), rest[s] = T(springs[s].rest);
        pinnedJ.assign(6 * std::size_t(S), T(0));
        adjSpring = m.adjSpring();
        adjSign.resize(adjSpring.size());
        for (int p = 0; p < m.particleCount(); ++p)
            for (int e = m.adjStart()[p]; e < m.adjStart()[p + 1]; ++e)
                adjSign[e] = springs[adjSpring[e]].i == p ? T(1) : T(-1);
    }
    // Eqs. 15-17 at positions xs (3n, particle-major), once per spring. Each spring's block of W,
    // -h^2 J, goes to W's slot s (zero where an end is pinned, and then J to pinnedJ, for the free
    // end's diagonal); with velocities vs, its term of b for the row of its i end,
    // h fm u + h^2 J (v_j - v_i), goes to bterm[3 s] (the j end's is the negative).
    void compute(const double* xs, const double* vs, T h, T h2, const unsigned char* pinned, bool compressionRule,
                 BlockMatrix<T>& W, ThreadPool& pool) {
        if (vs) bterm.resize(3 * si.size());
        pool.run(int(si.size()), [&](int begin, int end) {
            for (int s = begin; s < end; ++s) {
                const int i = si[s], j = sj[s];
                const SpringTerms<T> t = springTerms(T(xs[3 * j] - xs[3 * i]), T(xs[3 * j + 1] - xs[3 * i + 1]),
                                                     T(xs[3 * j + 2] - xs[3 * i + 2]), k[s], rest[s], compressionRule);
                T J[6];
                jacobianOf(t, J);
                const bool pinnedEnd = pinned[i] || pinned[j];
                if (pinnedEnd) std::copy(J, J + 6, &pinnedJ[6 * std::size_t(s)]);
                const T scale = pinnedEnd ? T(0) : -h2;
                T O[6];
                for (int q = 0; q < 6; ++q) O[q] = scale * J[q];
                W.put(W.n + s, O);
                if (vs) {
                    const T dq[3] = {T(vs[3 * j] - vs[3 * i]), T(vs[3 * j + 1] - vs[3 * i + 1]),
                                     T(vs[3 * j + 2] - vs[3 * i + 2])};
                    T Jq[3];
                    symmetricTimes(J, dq, Jq);
                    bterm[3 * std::size_t(s)] = h * t.fm * t.ux + h2 * Jq[0];
                    bterm[3 * std::size_t(s) + 1] = h * t.fm * t.uy + h2 * Jq[1];
                    bterm[3 * std::size_t(s) + 2] = h * t.fm * t.uz + h2 * Jq[2];
                }
            }
        });
    }
};

// The springs of a banded grid level (level 0, and re-discretized coarse levels), by band: slot p
// of band k joins particles p and p + o_k, as the bands of W hold W_{p, p + o_k}. The per-step
// passes then run down contiguous arrays and vectorize, as the paper's stencil step does; a slot
// with no spring has k = 0 and contributes exact zeros. Positions, velocities and the free-row
// mask are structure-of-arrays with `pad` zeros on both sides.
template <class T>
struct BandedSprings {
    int n = 0, pad = 0;
    std::vector<int> offsets;
    std::vector<T> k, rest;          // band-major, n per band
    std::vector<double> xyz, vel;    // 3 arrays of n + 2 pad each
    std::vector<T> freeRow;          // n + 2 pad: 1 where the particle is free
    std::vector<T> bterm;            // 3 arrays per band of btStride, pad zeros first
    std::size_t btStride = 0;
    // The springs' blocks of W in the form the product reads: W_{i, i + o} = -h^2 (a I + b u u^T) =
    // -(c I + g g^T) with c = h^2 a and g = h sqrt(b) u (b >= 0; zero where an end is pinned or
    // there is no spring), four arrays per band (g0 g1 g2 c) of springStride, pad zeros first.
    // Four numbers a block instead of six: a product at 129x129 and larger streams W from memory.
    std::vector<T> spring;
    std::size_t springStride = 0;

    bool used() const { return !offsets.empty(); }
    std::size_t len() const { return std::size_t(n) + 2 * std::size_t(pad); }
    const double* x(int a) const { return xyz.data() + a * len() + pad; }
    const double* v(int a) const { return vel.data() + a * len() + pad; }
    T* bt(int band, int a) { return bterm.data() + (3 * std::size_t(band) + a) * btStride + pad; }
    T* sp(int band, int q) { return spring.data() + (4 * std::size_t(band) + q) * springStride + pad; }
    const T* sp(int band, int q) const { return spring.data() + (4 * std::size_t(band) + q) * springStride + pad; }
};

template <class T>
struct BandSpringArgs {
    const double *x0, *x1, *x2, *v0, *v1, *v2;  // v0 null: no right-hand side
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
// or there is no spring) into the band, BlockMatrix::blocks and the compact arrays (BandedSprings::
// spring), and with velocities (WithRhs) the term
// of b for the lower end, h fm u + h^2 J (v_upper - v_lower) (the upper end's is the negative).
template <class T, bool WithRhs>
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
        if constexpr (WithRhs) {
            const T q0 = T(v0[p + d] - v0[p]), q1 = T(v1[p + d] - v1[p]), q2 = T(v2[p + d] - v2[p]);
            b0[p] = h * t.fm * t.ux + h2 * (J0 * q0 + J1 * q1 + J2 * q2);
            b1[p] = h * t.fm * t.uy + h2 * (J1 * q0 + J3 * q1 + J4 * q2);
            b2[p] = h * t.fm * t.uz + h2 * (J2 * q0 + J4 * q1 + J5 * q2);
        }
    }
    // The block copy in a loop of its own: interleaved stores in the loop above stop it vectorizing.
    if (!copy) return;
    for (int p = begin; p < end; ++p) {
        copy[6 * p] = o0[p], copy[6 * p + 1] = o1[p], copy[6 * p + 2] = o2[p];
        copy[6 * p + 3] = o3[p], copy[6 * p + 4] = o4[p], copy[6 * p + 5] = o5[p];
    }
}

// y (tile of rows) += O x for the spring blocks O = -(c I + g g^T) (BandedSprings::spring) and x
// (three arrays).
template <class T>
CLOTH_INLINE inline void addSpringTimes(const T* __restrict g0, const T* __restrict g1, const T* __restrict g2,
                                        const T* __restrict c, const T* __restrict x0, const T* __restrict x1,
                                        const T* __restrict x2, int count, T* __restrict y0, T* __restrict y1,
                                        T* __restrict y2) {
CLOTH_IVDEP
    for (int t = 0; t < count; ++t) {
        const T gx = g0[t] * x0[t] + g1[t] * x1[t] + g2[t] * x2[t];
        y0[t] -= c[t] * x0[t] + gx * g0[t];
        y1[t] -= c[t] * x1[t] + gx * g1[t];
        y2[t] -= c[t] * x2[t] + gx * g2[t];
    }
}

// bandedProduct for a banded level that carries a cloth: the diagonal band from W, the springs'
// blocks from their compact arrays S (four numbers a block instead of six).
template <class T>
CLOTH_SIMD_CLONES void springBandProduct(const BlockMatrix<T>& W, const BandedSprings<T>& S, const T* X0, const T* X1,
                                         const T* X2, const T* b, T* out, int begin, int end) {
    alignas(64) T y0[kTile], y1[kTile], y2[kTile];
    const std::size_t s = W.stride;
    const T* D = W.values.data() + W.pad;
    const int bands = int(S.offsets.size());
    for (int first = begin; first < end; first += kTile) {
        const int count = std::min(kTile, end - first);
        std::fill(y0, y0 + count, T(0)), std::fill(y1, y1 + count, T(0)), std::fill(y2, y2 + count, T(0));
        addBlockTimes(D + first, D + s + first, D + 2 * s + first, D + 3 * s + first, D + 4 * s + first,
                      D + 5 * s + first, X0 + first, X1 + first, X2 + first, count, y0, y1, y2);
        for (int k = 0; k < bands; ++k) {
            const int o = S.offsets[k];
            for (const int side : {1, -1}) {
                const int row = first + (side > 0 ? 0 : -o), col = first + side * o;
                addSpringTimes(S.sp(k, 0) + row, S.sp(k, 1) + row, S.sp(k, 2) + row, S.sp(k, 3) + row, X0 + col,
                               X1 + col, X2 + col, count, y0, y1, y2);
            }
        }
        storeTile(y0, y1, y2, count, b ? b + 3 * std::size_t(first) : nullptr, out + 3 * std::size_t(first));
    }
}

// Rows [begin, end) of a banded cloth level: D_i = base_i - sum over bands of (O_k[i] + O_k[i - o_k])
// (W_ii = base + h^2 sum_j J_ij, eq. 12, from the blocks O = -h^2 J) into band 0, and with
// velocities the springs' part of b_i, sum over bands of (bt_k[i] - bt_k[i - o_k]), into b (3n).
template <class T>
CLOTH_SIMD_CLONES void bandRowSums(BlockMatrix<T>& A, const T* base, BandedSprings<T>& S, bool withRhs, T* b,
                                   int begin, int end) {
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
                if (!withRhs) continue;
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
        if (withRhs)
            for (int t = 0; t < count; ++t)
                for (int c = 0; c < 3; ++c) b[3 * std::size_t(first + t) + c] = acc[6 + c][t];
    }
}

// A coarse grid cloth with the same rectangle, stiffness per spring kind and total mass as `fine`.
Model coarserCloth(const Model& fine, int cx, int cy) {
    const int nx = fine.gridNx(), ny = fine.gridNy();
    const Points& rest = fine.restPositions();
    GridDesc d;
    d.nx = cx, d.ny = cy;
    d.origin = rest.col(0);
    const Vec3 u = rest.col(nx - 1) - rest.col(0), v = rest.col((ny - 1) * nx) - rest.col(0);
    d.width = u.norm(), d.height = v.norm();
    d.axisU = u, d.axisV = v;
    d.totalMass = fine.totalMass();
    d.stiffness.bend = 0;
    for (const Spring& s : fine.springs())
        (s.kind == SpringKind::Structural ? d.stiffness.structural
                                          : s.kind == SpringKind::Shear ? d.stiffness.shear : d.stiffness.bend) = s.k;
    return Model::fromGrid(d);
}

}  // namespace

template <class T>
struct Multigrid<T>::Impl {
    MultigridSettings settings;
    std::shared_ptr<ThreadPool> pools;
    ThreadPool& pool;
    std::uint64_t modelId = 0;
    std::string coarseningName;

    struct Level {
        BlockMatrix<T> A;
        std::vector<T> xs;   // banded A: x as three arrays of xStride with A.pad zeros on both sides
        std::size_t xStride = 0;
        std::vector<T> dinv, active;  // 6n; 1 for a row with an unknown, 0 for a pinned (empty) one
        std::vector<T> x, b, r;       // 3n
        std::vector<T> kb, kc, kq, kq2;  // K-cycle levels: the right-hand side, c1, W c1, W c2
        Transfer P;                   // to the next coarser level (unused on the last)
        // Galerkin plan for the next level's blocks: dst block d gets sum over
        // [planStart[d], planStart[d+1]) of planW * this level's block planSrc.
        std::vector<int> planStart, planSrc;
        std::vector<T> planW;
        // Or, on nested grids (nestedGalerkinRow), by dimension: nestedX coarsens x (this level's
        // rows into the intermediate grid cx x ny, whose blocks go to `half`: band e's six arrays
        // at half[(6 e + q) * halfStride + halfPad]), nestedY then y (the intermediate rows into
        // the coarse rows); this level's grid sides; and where each coarse (band, row) lands: its
        // destination block (the diagonal I, or n_c + slot), -1 where the pair is off the coarse grid.
        std::vector<NestedTerm<T>> nestedX, nestedY;
        int halfBands = 0, halfPad = 0;
        std::size_t halfStride = 0;
        std::vector<T> half;
        int gridNx = 0, gridNy = 0;
        std::vector<int> nestedDst;
        // Levels that carry a cloth (level 0, and re-discretized coarse levels): its springs,
        // positions, pinned rows and the spring-free part of W_ii (mass, drag, damping).
        std::shared_ptr<const Model> cloth;
        SpringSet<T> springs;       // gathered levels
        BandedSprings<T> band;      // banded levels
        Transfer sample;  // positions of this level from the finer level's (re-discretized)
        std::vector<double> pos;
        std::vector<T> base;
        std::vector<unsigned char> pinned;
        // Level 0 of a grid with its bend springs collapsed (MultigridSettings::collapseBend; the
        // grid's nx, else 0): S is W with each bend spring's block moved onto the spring's halves,
        // and the Galerkin product reads S instead of A.
        int bendNx = 0;
        BlockMatrix<T> S;
        const BlockMatrix<T>& source() const { return bendNx ? S : A; }
    };
    std::vector<Level> levels;
    Eigen::LLT<Eigen::MatrixXd> coarsest;
    Eigen::LDLT<Eigen::MatrixXd> coarsestFallback;
    bool useFallback = false;
    std::vector<T> pinDv;  // level 0
    std::vector<double> partial;

    // MultigridSettings::floatCycles (T = double): the same system in float, whose cycles
    // precondition this level's CG. It shares the pool.
    std::unique_ptr<typename Multigrid<float>::Impl> lower;

    Impl(const MultigridSettings& s, std::shared_ptr<ThreadPool> shared = nullptr)
        : settings(s), pools(shared ? std::move(shared) : std::make_shared<ThreadPool>(s.threads)), pool(*pools) {
        if constexpr (std::is_same_v<T, double>)
            if (s.floatCycles) lower = std::make_unique<typename Multigrid<float>::Impl>(s, pools);
    }

    void prepare(const Model& model);
    void buildFine(const Model& model, const Environment& env, const State& state, const StepInput& input,
                   bool compressionRule);
    // floatCycles (T = float): level 0 as `fine`'s level 0 (the same model's double system),
    // rounded; b stays with fine's CG.
    void roundFine(const typename Multigrid<double>::Impl& fine);
    void useSprings(Level& L, const Model& cloth);
    template <class RowTerms>
    void buildCloth(int l, const double* xs, const double* vs, T h, T h2, bool compressionRule, const RowTerms& rowTerms);
    template <class RowTerms>
    void assembleCloth(int l, T h2, bool withRhs, const RowTerms& rowTerms);
    template <class RowTerms>
    void assembleBanded(int l, const double* xs, const double* vs, T h, T h2, bool compressionRule,
                        const RowTerms& rowTerms);
    void rediscretize(int l, T h2, bool compressionRule);
    bool nestedTerms(Level& fine, const Level& coarse, int nx, int ny);
    bool collapsePattern(Level& L, int nx);
    void collapseBends(Level& L);
    void galerkin(int l);
    void coarseOperators(T h2, bool compressionRule);
    // coarseOperators() unless the last ones may be reused (MultigridSettings::coarseEvery).
    void refreshCoarse(T h2, bool compressionRule);
    int coarseAge = -1;  // solves since the coarse operators were built (-1: none for this model)
    std::vector<unsigned char> coarsePinned;
    T coarseH2 = 0;
    bool coarseCompression = true;
    void factorCoarsest();
    void product(int l, const std::vector<T>& x, const std::vector<T>* b, std::vector<T>& out);
    void residual(int l, const std::vector<T>& x, const std::vector<T>& b, std::vector<T>& r) { product(l, x, &b, r); }
    void smooth(int l, bool residualKnown);
    void cycle(int l, bool residualKnown);
    void coarseSolve(int l);
    double norm(const std::vector<T>& v);
    bool converged(double rel, const std::vector<T>& r, const std::vector<T>& x);
    double dot(const std::vector<T>& a, const std::vector<T>& b);
    void precondition(const std::vector<T>& r, std::vector<T>& z);  // z = one cycle on r, from zero
    void stationary(double bNorm, MultigridStats& stats);
    void conjugateGradients(double bNorm, MultigridStats& stats);
    double start(std::vector<T>& x, std::vector<T>& r, double bNorm);
    bool warmStart() const {
        return settings.start == MultigridSettings::Start::Previous ||
               (settings.start == MultigridSettings::Start::Auto && settings.cycles == 0);
    }
    std::vector<T> cgX, cgR, cgZ, cgP, cgQ;
    std::vector<std::vector<T>> history;  // the last solves' dv, newest first, for MultigridSettings::start
    std::vector<std::vector<T>> historyW;  // scratch: W times each

    int chunks(int n) const { return (n + kChunk - 1) / kChunk; }
    T lastH2 = 0;
    bool lastCompression = true;
};

template <class T>
void Multigrid<T>::Impl::prepare(const Model& model) {
    modelId = model.id();
    history.clear();
    coarseAge = -1;
    const int n = model.particleCount();
    int nestedTransfers = 0;
    levels.clear();
    levels.emplace_back();
    {
        Level& L0 = levels[0];
        L0.A.n = n;
        L0.A.start = model.adjStart();
        L0.A.col = model.adjOther();
        L0.A.slot = model.adjSpring();
        L0.A.slots = model.springCount();
        useSprings(L0, model);
        L0.pinned.assign(n, 0);
        L0.base.assign(6 * std::size_t(n), T(0));
    }
    pinDv.assign(3 * std::size_t(n), T(0));

    using Coarsening = MultigridSettings::Coarsening;
    bool geometric = settings.coarsening == Coarsening::Geometric ||
                     (settings.coarsening == Coarsening::Auto && model.gridNx() > 0);
    int nx = model.gridNx(), ny = model.gridNy();
    std::ostringstream label;
    if (geometric && nx > 0) label << "geometric " << nx << "x" << ny;
    else if (geometric) label << "aggregation (geometric asked for, but the model is not a grid) " << n;
    else label << "aggregation " << n;
    geometric = geometric && nx > 0;
    const bool rediscretized = geometric && settings.coarseOperator == MultigridSettings::CoarseOperator::Rediscretized;
    if (settings.coarseOperator == MultigridSettings::CoarseOperator::Rediscretized && !geometric)
        label << " (Galerkin: re-discretization needs a grid)";
    const bool collapsed = settings.collapseBend && geometric && !rediscretized && collapsePattern(levels[0], nx);

    // Scalar stiffness Laplacian for aggregation (coarsened along with the blocks).
    Eigen::SparseMatrix<double, Eigen::RowMajor> lap;
    if (!geometric) {
        std::vector<Eigen::Triplet<double>> t;
        for (const Spring& s : model.springs()) {
            t.emplace_back(s.i, s.j, -s.k), t.emplace_back(s.j, s.i, -s.k);
            t.emplace_back(s.i, s.i, s.k), t.emplace_back(s.j, s.j, s.k);
        }
        lap.resize(n, n);
        lap.setFromTriplets(t.begin(), t.end());
    }

    while (levels.back().A.n > settings.coarsestParticles) {
        Transfer P;
        const int fineNx = nx, fineNy = ny;
        if (geometric) {
            const int cx = coarserSide(nx), cy = coarserSide(ny);
            if (cx == nx && cy == ny) break;
            P = gridTransfer(nx, ny, cx, cy);
            Level coarse;
            if (rediscretized) {
                const Model& fineCloth = levels.size() == 1 ? model : *levels.back().cloth;
                coarse.cloth = std::make_shared<const Model>(coarserCloth(fineCloth, cx, cy));
                coarse.sample = gridTransfer(cx, cy, nx, ny);  // coarse nodes sampled on the finer grid
            }
            nx = cx, ny = cy;
            label << " " << P.label;
            levels.back().P = std::move(P);
            if (rediscretized) {
                const Model& c = *coarse.cloth;
                coarse.A.n = c.particleCount();
                coarse.A.start = c.adjStart();
                coarse.A.col = c.adjOther();
                coarse.A.slot = c.adjSpring();
                coarse.A.slots = c.springCount();
                useSprings(coarse, c);
                coarse.pinned.assign(coarse.A.n, 0);
                coarse.base.assign(6 * std::size_t(coarse.A.n), T(0));
                coarse.pos.assign(3 * std::size_t(coarse.A.n), 0.0);
                levels.push_back(std::move(coarse));
                continue;
            }
            levels.push_back(std::move(coarse));
        } else {
            P = aggregationTransfer(lap);
            if (P.coarse >= levels.back().A.n) break;  // no coarsening left (every point its own aggregate)
            Eigen::SparseMatrix<double, Eigen::RowMajor> Ps(P.fine, P.coarse);
            std::vector<Eigen::Triplet<double>> t;
            for (int i = 0; i < P.fine; ++i)
                for (int e = P.pStart[i]; e < P.pStart[i + 1]; ++e) t.emplace_back(i, P.pCol[e], P.pW[e]);
            Ps.setFromTriplets(t.begin(), t.end());
            lap = Eigen::SparseMatrix<double, Eigen::RowMajor>(Ps.transpose() * lap * Ps);
            lap.prune(1e-12, 1);
            label << " " << P.label;
            levels.back().P = std::move(P);
            levels.emplace_back();
        }
        // Galerkin: the coarse pattern (blocks (I, J) reached by some fine block (i, j) with
        // P_iI P_jJ != 0) and the plan.
        Level& fine = levels[levels.size() - 2];
        Level& coarse = levels.back();
        const BlockMatrix<T>& src = fine.source();
        const Transfer& Pf = fine.P;
        const int nc = Pf.coarse, nf = fine.A.n;
        auto forPairs = [&](int i, int j, auto&& fn) {
            for (int a = Pf.pStart[i]; a < Pf.pStart[i + 1]; ++a)
                for (int b = Pf.pStart[j]; b < Pf.pStart[j + 1]; ++b) fn(Pf.pCol[a], Pf.pCol[b], Pf.pW[a] * Pf.pW[b]);
        };
        std::vector<std::vector<int>> cols(nc);
        for (int i = 0; i < nf; ++i) {
            auto add = [&](int I, int J, double) {
                if (I != J) cols[I].push_back(J);
            };
            forPairs(i, i, add);
            for (int e = src.start[i]; e < src.start[i + 1]; ++e) forPairs(i, src.col[e], add);
        }
        coarse.A.n = nc;
        coarse.A.start.assign(1, 0);
        for (auto& c : cols) {
            std::sort(c.begin(), c.end());
            c.erase(std::unique(c.begin(), c.end()), c.end());
            coarse.A.col.insert(coarse.A.col.end(), c.begin(), c.end());
            coarse.A.start.push_back(int(coarse.A.col.size()));
        }
        coarse.A.numberSlots();
        if (geometric && nestedTerms(fine, coarse, fineNx, fineNy)) {
            ++nestedTransfers;
            continue;
        }
        // The plan fills the diagonal and the slots from (I, J) with I < J; the fine matrix is
        // symmetric, so the contributions with I > J are the same blocks mirrored.
        std::vector<std::pair<int, int>> pairs;  // (dst, src)
        std::vector<double> weights;
        for (int i = 0; i < nf; ++i) {
            auto add = [&](int src) {
                return [&, src](int I, int J, double w) {
                    if (I > J) return;
                    pairs.push_back({I == J ? I : nc + coarse.A.slot[coarse.A.entryOf(I, J)], src});
                    weights.push_back(w);
                };
            };
            forPairs(i, i, add(i));
            for (int e = src.start[i]; e < src.start[i + 1]; ++e) forPairs(i, src.col[e], add(nf + src.slot[e]));
        }
        const int dsts = nc + coarse.A.slots;
        fine.planStart.assign(dsts + 1, 0);
        for (const auto& p : pairs) ++fine.planStart[p.first + 1];
        for (int d = 0; d < dsts; ++d) fine.planStart[d + 1] += fine.planStart[d];
        std::vector<int> fillAt(fine.planStart.begin(), fine.planStart.end() - 1);
        fine.planSrc.resize(pairs.size());
        fine.planW.resize(pairs.size());
        for (std::size_t q = 0; q < pairs.size(); ++q) {
            const int at = fillAt[pairs[q].first]++;
            fine.planSrc[at] = pairs[q].second;
            fine.planW[at] = T(weights[q]);
        }
    }
    if (rediscretized) {
        label << " (re-discretized)";
    } else {
        label << " (Galerkin";
        if (collapsed) label << " with bend springs collapsed";
        if (nestedTransfers > 0)
            label << "; by stencil on " << nestedTransfers << " of " << levels.size() - 1 << " coarse levels";
        label << ")";
        if (settings.collapseBend && geometric && !collapsed)
            label << " (bend springs kept: level 0 is not a banded grid whose bend springs have both halves)";
    }
    coarseningName = label.str();
    for (Level& L : levels) {
        // The last level is factored, not multiplied; a plan reads its source level's block copy.
        const bool planReads = !L.planStart.empty();
        L.A.layout(&L != &levels.back() || L.band.used(), planReads && !L.bendNx);
        if (L.bendNx) L.S.layout(true, planReads);
        L.xStride = spacedLength<T>(std::size_t(L.A.n + 2 * L.A.pad));
        L.xs.assign(L.A.banded() ? 3 * L.xStride : 0, T(0));
        L.dinv.assign(6 * std::size_t(L.A.n), T(0));
        L.active.assign(L.A.n, T(0));
        for (auto* v : {&L.x, &L.b, &L.r}) v->assign(3 * std::size_t(L.A.n), T(0));
    }
}

// The terms of nestedGalerkinRow for fine (an nx x ny grid) and its coarse level, whose pattern is
// set; false (the plan is used) unless both sides are odd and at least 5, the coarse rows are at
// least settings.stencilGalerkinMinRow long, the fine level will be banded, every band is a 2D
// offset within 2 points, and the terms reach every coarse entry.
template <class T>
bool Multigrid<T>::Impl::nestedTerms(Level& fine, const Level& coarse, int nx, int ny) {
    if (nx % 2 == 0 || ny % 2 == 0 || nx < 5 || ny < 5 || (nx + 1) / 2 < settings.stencilGalerkinMinRow) return false;
    const std::vector<int> offsets = fine.source().bandOffsets();  // what layout() will choose
    if (offsets.empty()) return false;
    // The fine band of each 2D offset (dx, dy), |dx|, |dy| <= 2 (-1: none).
    int bandOf[5][5];
    for (auto& row : bandOf) std::fill(row, row + 5, -1);
    bandOf[2][2] = 0;
    for (std::size_t k = 0; k < offsets.size(); ++k) {
        const int o = offsets[k], dy = (o + 2) / nx, dx = o - dy * nx;
        if (dy > 2 || dx < -2 || dx > 2) return false;
        bandOf[dy + 2][dx + 2] = int(k) + 1;
        bandOf[2 - dy][2 - dx] = int(k) + 1;
    }
    const auto D = nestedOffsets();
    const int cx = (nx + 1) / 2, cy = (ny + 1) / 2, nc = cx * cy;
    auto weight = [](int a) { return a == 0 ? 1.0 : 0.5; };  // bilinear P, one dimension
    // The intermediate grid's offsets (Dx, dy), upper half: a fine pair (2X + a, 2(X + Dx) + b)
    // in x, the fine offset in y. halfOf: the band of each offset (either orientation; -1: none).
    std::vector<std::pair<int, int>> halfOffsets = {{0, 0}};
    int halfOf[5][5];
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
                    halfOf[dy + 2][Dx + 2] = halfOf[2 - dy][2 - Dx] = int(halfOffsets.size());
                    halfOffsets.push_back({Dx, dy});
                }
    // One dimension's terms: output offset o = (ox, oy) gets, for a, b in {-1, 0, 1}, the source
    // band of the offset with 2 o + b - a along the dimension coarsened and o along the other.
    // x: T((X, y), (X + Dx, y + dy)) = sum over a, b of w_a w_b W((2X + a, y), (2X + 2Dx + b, y + dy));
    // y: W_c((X, Y), (X + Dx, Y + Dy)) = sum over a, b of w_a w_b T((X, 2Y + a), (X + Dx, 2Y + 2Dy + b)).
    auto termsOf = [&](const std::vector<std::pair<int, int>>& outs, const int (*source)[5], bool alongX, int pitch) {
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
    };
    std::vector<NestedTerm<T>> termsX = termsOf(halfOffsets, bandOf, true, nx), termsY = termsOf(D, halfOf, false, cx);
    // Where each (coarse band, row) goes; every entry of the coarse pattern must be one of them.
    std::vector<int> dst(D.size() * nc, -1);
    int reached = 0;
    for (int I = 0; I < nc; ++I) {
        const int X = I % cx, Y = I / cx;
        dst[I] = I;
        for (std::size_t d = 1; d < D.size(); ++d) {
            const int JX = X + D[d].first, JY = Y + D[d].second;
            if (JX < 0 || JX >= cx || JY >= cy) continue;
            const int e = coarse.A.entryOf(I, JY * cx + JX);
            if (e < 0) continue;
            dst[d * nc + I] = nc + coarse.A.slot[e];
            ++reached;
        }
    }
    if (2 * reached != coarse.A.entries()) return false;
    fine.nestedX = std::move(termsX);
    fine.nestedY = std::move(termsY);
    fine.halfBands = int(halfOffsets.size());
    fine.halfPad = 2 * cx + 2;  // the most negative shift of a term of nestedY
    fine.halfStride = spacedLength<T>(std::size_t(cx) * ny + 2 * std::size_t(fine.halfPad));
    fine.half.assign(6 * std::size_t(fine.halfBands) * fine.halfStride, T(0));
    fine.nestedDst = std::move(dst);
    fine.gridNx = nx, fine.gridNy = ny;
    return true;
}

// Level 0's pattern without its bend springs, for S (collapseBend); false (nothing collapsed) unless
// level 0 is a banded grid (nx >= 5) whose bands are the structural (1, nx), shear (nx - 1,
// nx + 1) and bend (2, 2 nx) offsets, with both bend bands, and every bend spring's two halves are
// pairs of the pattern.
template <class T>
bool Multigrid<T>::Impl::collapsePattern(Level& L, int nx) {
    const BlockMatrix<T>& A = L.A;
    const std::vector<int>& offsets = L.band.offsets;  // = A.bandOffsets() (useSprings)
    auto has = [&](int o) { return std::binary_search(offsets.begin(), offsets.end(), o); };
    if (nx < 5 || !L.band.used() || !has(1) || !has(2) || !has(nx) || !has(2 * nx)) return false;
    for (const int o : offsets)
        if (o != 1 && o != 2 && o != nx - 1 && o != nx && o != nx + 1 && o != 2 * nx) return false;
    const int n = A.n;
    auto linked = [&A](int i, int j) {  // level 0's rows are in the model's order, not sorted
        return std::find(A.col.begin() + A.start[i], A.col.begin() + A.start[i + 1], j) != A.col.begin() + A.start[i + 1];
    };
    for (const int o : {2, 2 * nx}) {
        const std::size_t k = std::size_t(std::lower_bound(offsets.begin(), offsets.end(), o) - offsets.begin());
        for (int p = 0; p + o < n; ++p)
            if (L.band.k[k * n + p] != T(0) && (!linked(p, p + o / 2) || !linked(p + o / 2, p + o))) return false;
    }
    BlockMatrix<T>& S = L.S;
    S = BlockMatrix<T>{};
    S.n = n;
    S.start.assign(1, 0);
    for (int i = 0; i < n; ++i) {
        for (int e = A.start[i]; e < A.start[i + 1]; ++e) {
            const int o = std::abs(A.col[e] - i);
            if (o != 2 && o != 2 * nx) S.col.push_back(A.col[e]);
        }
        std::sort(S.col.begin() + S.start.back(), S.col.end());  // the order a plan then sums in
        S.start.push_back(int(S.col.size()));
    }
    std::vector<int> kept;
    for (const int o : offsets)
        if (o != 2 && o != 2 * nx) kept.push_back(o);
    S.numberSlotsByBand(kept);
    L.bendNx = nx;
    return true;
}

// A level that carries a cloth (its A's pattern set from the cloth's springs): banded springs
// where A can be banded, with A's slots renumbered band-major (slot k n + p: band k, row p, holes
// included), else the gathered spring set (slot = spring).
template <class T>
void Multigrid<T>::Impl::useSprings(Level& L, const Model& cloth) {
    BandedSprings<T>& B = L.band;
    B.offsets = L.A.bandOffsets();
    if (!B.used()) {
        L.springs.assign(cloth);
        return;
    }
    const int n = L.A.n, bands = int(B.offsets.size());
    auto bandOf = [&B](int d) { return int(std::lower_bound(B.offsets.begin(), B.offsets.end(), d) - B.offsets.begin()); };
    B.n = n;
    B.pad = B.offsets.back();
    B.k.assign(std::size_t(bands) * n, T(0));
    B.rest.assign(std::size_t(bands) * n, T(0));
    for (const Spring& sp : cloth.springs()) {
        const int lo = int(std::min(sp.i, sp.j));
        const std::size_t at = std::size_t(bandOf(int(std::max(sp.i, sp.j)) - lo)) * n + lo;
        B.k[at] = T(sp.k), B.rest[at] = T(sp.rest);
    }
    L.A.numberSlotsByBand(B.offsets);
    B.xyz.assign(3 * B.len(), 0.0);
    B.vel.assign(3 * B.len(), 0.0);
    B.freeRow.assign(B.len(), T(0));
    B.btStride = spacedLength<T>(std::size_t(n + B.pad));
    B.bterm.assign(3 * std::size_t(bands) * B.btStride, T(0));
    B.springStride = spacedLength<T>(std::size_t(n + B.pad));
    B.spring.assign(4 * std::size_t(bands) * B.springStride, T(0));
}

template <class T>
template <class RowTerms>
void Multigrid<T>::Impl::buildCloth(int l, const double* xs, const double* vs, T h, T h2, bool compressionRule,
                                    const RowTerms& rowTerms) {
    Level& L = levels[l];
    if (L.band.used()) {
        assembleBanded(l, xs, vs, h, h2, compressionRule, rowTerms);
        return;
    }
    L.springs.compute(xs, vs, h, h2, L.pinned.data(), compressionRule, L.A, pool);
    assembleCloth(l, h2, vs != nullptr, rowTerms);
}

// W (and with velocities vs, b) of a banded cloth level: the springs band by band
// (bandSpringKernel), the row sums (bandRowSums), then, for each spring with a pinned end, h^2 J
// on the free end's diagonal and h^2 J dv_pinned in its b (the block itself is zero: the pinned
// particle is not an unknown), then per row the terms of b without springs (rowTerms), the
// inverse diagonal, and empty rows for pinned particles. The same W and b as assembleCloth.
template <class T>
template <class RowTerms>
void Multigrid<T>::Impl::assembleBanded(int l, const double* xs, const double* vs, T h, T h2, bool compressionRule,
                                        const RowTerms& rowTerms) {
    Level& L = levels[l];
    BandedSprings<T>& B = L.band;
    BlockMatrix<T>& A = L.A;
    const int n = A.n, bands = int(B.offsets.size());
    const bool withRhs = vs != nullptr;
    pool.run(n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            for (int a = 0; a < 3; ++a) {
                B.xyz[a * B.len() + B.pad + i] = xs[3 * std::size_t(i) + a];
                if (withRhs) B.vel[a * B.len() + B.pad + i] = vs[3 * std::size_t(i) + a];
            }
            B.freeRow[B.pad + i] = L.pinned[i] ? T(0) : T(1);
        }
    });
    BandSpringArgs<T> args[BlockMatrix<T>::kMaxBands];
    for (int k = 0; k < bands; ++k) {
        BandSpringArgs<T>& a = args[k];
        a.x0 = B.x(0), a.x1 = B.x(1), a.x2 = B.x(2);
        a.v0 = withRhs ? B.v(0) : nullptr, a.v1 = B.v(1), a.v2 = B.v(2);
        a.k = &B.k[std::size_t(k) * n], a.rest = &B.rest[std::size_t(k) * n];
        a.freeRow = B.freeRow.data() + B.pad;
        for (int c = 0; c < 6; ++c) a.o[c] = A.values.data() + (6 * std::size_t(k + 1) + c) * A.stride + A.pad;
        a.copy = A.blocks.empty() ? nullptr : &A.blocks[6 * (std::size_t(n) + std::size_t(k) * n)];
        for (int c = 0; c < 3; ++c) a.bt[c] = B.bt(k, c);
        for (int q = 0; q < 4; ++q) a.g[q] = B.sp(k, q);
        a.offset = B.offsets[k];
        a.h = h, a.h2 = h2;
        a.compressionRule = compressionRule;
    }
    // The springs and the row sums in one pass, tile by tile, so that the row sums read the
    // blocks while they are in cache: row r sums slots r and r - o_k, so once a tile's slots are
    // written, its rows are complete, except the first `reach` rows of a chunk after the first
    // (their slots r - o_k belong to the chunk before), which are summed after the pass. Each
    // row's sum is the same whoever computes it: the same bits for any thread count.
    const int reach = B.offsets.back();
    std::vector<std::pair<int, int>> seams;
    std::mutex seamsMutex;
    pool.run(n, [&](int begin, int end) {
        const int ready = begin == 0 ? 0 : std::min(end, begin + reach);
        for (int first = begin; first < end; first += kTile) {
            const int last = std::min(end, first + kTile);
            for (int k = 0; k < bands; ++k) {
                if (withRhs) bandSpringKernel<T, true>(args[k], first, last);
                else bandSpringKernel<T, false>(args[k], first, last);
            }
            const int from = std::max(first, ready);
            if (from < last) bandRowSums(A, L.base.data(), B, withRhs, L.b.data(), from, last);
        }
        if (ready > begin) {
            const std::lock_guard<std::mutex> lock(seamsMutex);
            seams.push_back({begin, ready});
        }
    });
    for (const auto& [from, to] : seams) bandRowSums(A, L.base.data(), B, withRhs, L.b.data(), from, to);
    T* D = A.values.data() + A.pad;
    const std::size_t st = A.stride;
    for (int p = 0; p < n; ++p) {  // springs with a pinned end (few; in a fixed order)
        if (!L.pinned[p]) continue;
        for (int k = 0; k < bands; ++k) {
            const int o = B.offsets[k];
            for (const int q : {p + o, p - o}) {
                const int lo = std::min(p, q);
                if (q < 0 || q >= n || L.pinned[q] || B.k[std::size_t(k) * n + lo] == T(0)) continue;
                const SpringTerms<T> t = springTerms(T(B.x(0)[lo + o] - B.x(0)[lo]), T(B.x(1)[lo + o] - B.x(1)[lo]),
                                                     T(B.x(2)[lo + o] - B.x(2)[lo]), B.k[std::size_t(k) * n + lo],
                                                     B.rest[std::size_t(k) * n + lo], compressionRule);
                T J[6];
                jacobianOf(t, J);
                for (int c = 0; c < 6; ++c) D[c * st + q] += h2 * J[c];
                if (withRhs) {
                    T Jq[3];
                    symmetricTimes(J, &pinDv[3 * std::size_t(p)], Jq);
                    for (int a = 0; a < 3; ++a) L.b[3 * std::size_t(q) + a] += h2 * Jq[a];
                }
            }
        }
    }
    pool.run(n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            const bool free = !L.pinned[i];
            T Di[6];
            for (int c = 0; c < 6; ++c) Di[c] = free ? D[c * st + i] : T(0);
            A.put(i, Di);
            symmetricInverse(Di, &L.dinv[6 * std::size_t(i)]);
            L.active[i] = free ? T(1) : T(0);
            T* bi = &L.b[3 * std::size_t(i)];
            if (withRhs) {
                rowTerms(i, bi);
                if (!free) bi[0] = bi[1] = bi[2] = T(0);
            }
        }
    });
}

// W of a gathered level that carries a cloth (a mesh; banded levels: assembleBanded), from its
// springs' blocks (SpringSet::compute, which wrote
// W_ij = -h^2 J_ij, eqs. 16, 17): W_ii = base_i + h^2 sum_j J_ij (eq. 12); rows and columns of
// pinned particles are zero. With a right-hand side (level 0): b_i = the sum of its springs'
// terms (SpringSet::bterm, signed by the end) + h^2 J_ij dv_j for each pinned neighbour j (its
// prescribed change, eq. 7) + rowTerms(i, b_i) (gravity, drag, external force).
template <class T>
template <class RowTerms>
void Multigrid<T>::Impl::assembleCloth(int l, T h2, bool withRhs, const RowTerms& rowTerms) {
    Level& L = levels[l];
    const int n = L.A.n;
    const SpringSet<T>& S = L.springs;
    pool.run(n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            T* dinv = &L.dinv[6 * std::size_t(i)];
            T* bi = &L.b[3 * std::size_t(i)];
            if (L.pinned[i]) {
                const T zero[6] = {0, 0, 0, 0, 0, 0};
                L.A.put(i, zero);
                for (int q = 0; q < 6; ++q) dinv[q] = T(0);
                if (withRhs) bi[0] = bi[1] = bi[2] = T(0);
                L.active[i] = T(0);
                continue;
            }
            L.active[i] = T(1);
            T K[6] = {0, 0, 0, 0, 0, 0}, r[3] = {0, 0, 0};
            for (int e = L.A.start[i]; e < L.A.start[i + 1]; ++e) {
                const int s = L.A.slot[e], j = L.A.col[e];
                if (L.pinned[j]) {  // the stored block is zero; the diagonal still has the spring
                    const T* J = &S.pinnedJ[6 * std::size_t(s)];
                    for (int q = 0; q < 6; ++q) K[q] += h2 * J[q];
                    if (withRhs) {
                        T Jq[3];
                        symmetricTimes(J, &pinDv[3 * std::size_t(j)], Jq);
                        for (int a = 0; a < 3; ++a) r[a] += h2 * Jq[a];
                    }
                } else {
                    const T* O = L.A.block(n + s);
                    for (int q = 0; q < 6; ++q) K[q] -= O[q];
                }
                if (withRhs)
                    for (int a = 0; a < 3; ++a) r[a] += S.adjSign[e] * S.bterm[3 * std::size_t(s) + a];
            }
            for (int q = 0; q < 6; ++q) K[q] += L.base[6 * std::size_t(i) + q];
            L.A.put(i, K);
            symmetricInverse(K, dinv);
            if (withRhs) {
                rowTerms(i, r);
                bi[0] = r[0], bi[1] = r[1], bi[2] = r[2];
            }
        }
    });
}

// Level 0 at this state (the system of system.cpp's buildSystem): f (eq. 15, gravity, drag,
// external), W (eqs. 12, 16, 17 with drag and h C_i), and
// b_i = h f_i + h^2 sum_j J_ij (v_j - v_i) (eq. 7) with pinned neighbours' prescribed dv in it.
template <class T>
void Multigrid<T>::Impl::buildFine(const Model& model, const Environment& env, const State& state,
                                   const StepInput& input, bool compressionRule) {
    const int n = model.particleCount();
    const T h = T(input.h), h2 = h * h, c = T(env.drag);
    const T g[3] = {T(env.gravity.x()), T(env.gravity.y()), T(env.gravity.z())};
    const double* xs = state.x.data();
    const double* vs = state.v.data();
    const double* ext = input.externalForce ? input.externalForce->data() : nullptr;
    Level& L = levels[0];
    std::fill(L.pinned.begin(), L.pinned.end(), 0);
    std::fill(pinDv.begin(), pinDv.end(), T(0));
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= n) continue;
        L.pinned[p.particle] = 1;
        const Vec3 dv = pinVelocityChange(p, state.x.col(p.particle), state.v.col(p.particle), input.h);
        for (int a = 0; a < 3; ++a) pinDv[3 * p.particle + a] = T(dv[a]);
    }
    const auto& mass = model.masses();
    for (int i = 0; i < n; ++i) {
        T* B = &L.base[6 * std::size_t(i)];
        const T md = T(mass[i]) * (T(1) + h * c);
        B[0] = B[3] = B[5] = md;
        B[1] = B[2] = B[4] = T(0);
        if (input.damping) {
            const Mat3& C = (*input.damping)[i];
            B[0] += h * T(C(0, 0)), B[1] += h * T(C(0, 1)), B[2] += h * T(C(0, 2));
            B[3] += h * T(C(1, 1)), B[4] += h * T(C(1, 2)), B[5] += h * T(C(2, 2));
        }
    }
    buildCloth(0, xs, vs, h, h2, compressionRule, [&](int i, T* r) {  // + h (m (g - c v) + external)
        const T m = T(mass[i]);
        for (int a = 0; a < 3; ++a)
            r[a] += h * (m * (g[a] - c * T(vs[3 * i + a])) + (ext ? T(ext[3 * i + a]) : T(0)));
    });
    lastH2 = h2;
    lastCompression = compressionRule;
    if (levels.size() > 1 && levels[1].cloth) L.pos.assign(xs, xs + 3 * std::size_t(n));
}

// What the cycles read of level 0, and the coarse levels are built from: W (bands, or blocks; the
// block copy where kept), its inverse diagonal blocks, the free rows, the pinned particles, and
// for re-discretized coarse levels the diagonal base and the positions. Both hierarchies were
// prepared for the same model with the same settings, so their patterns and layouts agree; only
// the band stride (padded per type) differs.
template <class T>
void Multigrid<T>::Impl::roundFine(const typename Multigrid<double>::Impl& fine) {
    const auto& F = fine.levels[0];
    Level& L = levels[0];
    const int n = L.A.n;
    auto round = [&](const std::vector<double>& from, std::vector<T>& to) {  // arrays of blocks, 6 numbers each
        to.resize(from.size());
        pool.run(int(from.size() / 6), [&](int begin, int end) {
            for (std::size_t q = 6 * std::size_t(begin); q < 6 * std::size_t(end); ++q) to[q] = T(from[q]);
        });
    };
    if (L.A.banded()) {
        const std::size_t arrays = 6 * (L.A.offsets.size() + 1);
        pool.run(n, [&](int begin, int end) {
            for (std::size_t a = 0; a < arrays; ++a) {
                const double* src = F.A.values.data() + a * F.A.stride + F.A.pad;
                T* dst = L.A.values.data() + a * L.A.stride + L.A.pad;
                for (int i = begin; i < end; ++i) dst[i] = T(src[i]);
            }
            for (int i = begin; i < end; ++i) L.band.freeRow[L.band.pad + i] = T(F.band.freeRow[F.band.pad + i]);
            for (int k = 0; k < int(L.band.offsets.size()); ++k)
                for (int q = 0; q < 4; ++q) {
                    const double* src = F.band.sp(k, q);
                    T* dst = L.band.sp(k, q);
                    for (int i = begin; i < end; ++i) dst[i] = T(src[i]);
                }
        });
    } else {
        round(F.A.values, L.A.values);
    }
    if (!L.A.blocks.empty()) round(F.A.blocks, L.A.blocks);
    round(F.dinv, L.dinv);
    round(F.base, L.base);
    pool.run(n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) L.active[i] = T(F.active[i]);
    });
    L.pinned = F.pinned;
    L.pos = F.pos;
    lastH2 = T(fine.lastH2);
    lastCompression = fine.lastCompression;
}

// Level l + 1 re-discretized: positions sampled from level l, the coarse cloth's springs there,
// its diagonal base (mass, drag, damping) restricted from level l (sum_i P_iI base_i), a coarse
// particle pinned where its nearest finer particle is.
template <class T>
void Multigrid<T>::Impl::rediscretize(int l, T h2, bool compressionRule) {
    const Level& F = levels[l];
    Level& C = levels[l + 1];
    const Transfer& S = C.sample;
    const Transfer& P = F.P;
    pool.run(C.A.n, [&](int begin, int end) {
        for (int I = begin; I < end; ++I) {
            double x[3];
            S.gather(true, I, F.pos.data(), x);
            for (int a = 0; a < 3; ++a) C.pos[3 * std::size_t(I) + a] = x[a];
            T base[6] = {0, 0, 0, 0, 0, 0};
            double best = -1;
            bool pinned = false;
            for (int e = P.rStart[I]; e < P.rStart[I + 1]; ++e) {
                const int i = P.rRow[e];
                symAxpy(T(P.rW[e]), &F.base[6 * std::size_t(i)], base);
                if (P.rW[e] > best) best = P.rW[e], pinned = F.pinned[i] != 0;
            }
            std::copy(base, base + 6, &C.base[6 * std::size_t(I)]);
            C.pinned[I] = pinned;
        }
    });
    buildCloth(l + 1, C.pos.data(), nullptr, T(0), h2, compressionRule, [](int, T*) {});
}

template <class T>
void Multigrid<T>::Impl::coarseOperators(T h2, bool compressionRule) {
    for (int l = 0; l + 1 < int(levels.size()); ++l) {
        if (levels[l + 1].cloth) rediscretize(l, h2, compressionRule);
        else galerkin(l);
    }
    factorCoarsest();
}

// With one level the coarsest is the finest, which changes every step.
template <class T>
void Multigrid<T>::Impl::refreshCoarse(T h2, bool compressionRule) {
    const Level& L = levels[0];
    const bool reuse = levels.size() > 1 && coarseAge >= 0 && coarseAge + 1 < settings.coarseEvery &&
                       h2 == coarseH2 && compressionRule == coarseCompression && L.pinned == coarsePinned;
    if (reuse) {
        ++coarseAge;
        return;
    }
    coarseOperators(h2, compressionRule);
    coarseAge = 0;
    coarsePinned = L.pinned;
    coarseH2 = h2;
    coarseCompression = compressionRule;
}

// S = W with its bend springs collapsed. A bend spring (i, j = i + 2 d) with block O = W_ij and
// midpoint m = i + d is replaced by two springs (i, m), (m, j) with block 2 O each: the same energy
// for a displacement linear from i to j, so the coarse levels still see the bend springs' share of
// the stretching stiffness, and P^T S P keeps the 9-point stencil of S (P^T W P has 25 points:
// a bend spring from an odd point reaches two coarse points away). As a change of W:
//   W_ij -= O (to zero), W_im += 2 O, W_mj += 2 O, W_ii -= O, W_jj -= O, W_mm -= 4 O,
// then rows and columns of pinned particles are zero again. (A bend spring with a pinned end has
// O = 0 and is already on its free end's diagonal.) S is symmetric positive definite where W is:
// each collapsed spring is a spring with twice the block.
namespace {
template <class T>
CLOTH_SIMD_CLONES void collapseBendRows(const BlockMatrix<T>& A, BlockMatrix<T>& S, const T* act, int nx, int begin,
                                        int end) {
    auto bandOf = [](const BlockMatrix<T>& M, int o) {
        return o == 0 ? 0 : 1 + int(std::lower_bound(M.offsets.begin(), M.offsets.end(), o) - M.offsets.begin());
    };
    const int bx = bandOf(A, 1), by = bandOf(A, nx), ox = bandOf(A, 2), oy = bandOf(A, 2 * nx);
    const int sx = bandOf(S, 1), sy = bandOf(S, nx);
    for (int c = 0; c < 6; ++c) {
        auto a = [&](int k) { return A.values.data() + (6 * std::size_t(k) + c) * A.stride + A.pad; };
        auto o = [&](int k) { return S.values.data() + (6 * std::size_t(k) + c) * S.stride + S.pad; };
        const T *__restrict D = a(0), *__restrict Bx = a(bx), *__restrict By = a(by);
        const T *__restrict Ox = a(ox), *__restrict Oy = a(oy);
        T *__restrict SD = o(0), *__restrict Sx = o(sx), *__restrict Sy = o(sy);
CLOTH_IVDEP
        for (int i = begin; i < end; ++i) {
            SD[i] = act[i] * (D[i] - (Ox[i] + Ox[i - 2]) - T(4) * Ox[i - 1] - (Oy[i] + Oy[i - 2 * nx]) - T(4) * Oy[i - nx]);
            Sx[i] = act[i] * act[i + 1] * (Bx[i] + T(2) * (Ox[i] + Ox[i - 1]));
            Sy[i] = act[i] * act[i + nx] * (By[i] + T(2) * (Oy[i] + Oy[i - nx]));
        }
        for (const int d : {nx - 1, nx + 1})  // the shear bands, unchanged
            if (std::binary_search(S.offsets.begin(), S.offsets.end(), d))
                std::copy(a(bandOf(A, d)) + begin, a(bandOf(A, d)) + end, o(bandOf(S, d)) + begin);
    }
}
}  // namespace

template <class T>
void Multigrid<T>::Impl::collapseBends(Level& L) {
    const BlockMatrix<T>& A = L.A;
    BlockMatrix<T>& S = L.S;
    const T* act = L.band.freeRow.data() + L.band.pad;
    pool.run(A.n, [&](int begin, int end) {
        collapseBendRows(A, S, act, L.bendNx, begin, end);
        if (!S.blocks.empty()) S.copyBandsToBlocks(begin, end);  // a plan reads S
    });
}

// Level l + 1's blocks from level l's (or, with bend springs collapsed, from its S): W_c = P^T W P.
template <class T>
void Multigrid<T>::Impl::galerkin(int l) {
    if (levels[l].bendNx) collapseBends(levels[l]);
    const Level& F = levels[l];
    const BlockMatrix<T>& W = F.source();
    Level& C = levels[l + 1];
    if (!F.nestedX.empty()) {
        const int nx = F.gridNx, ny = F.gridNy, cx = (nx + 1) / 2, cy = (ny + 1) / 2, nc = C.A.n;
        const auto D = nestedOffsets();
        const int bands = int(D.size());
        // x first: every fine row into the intermediate grid (its pad stays zero).
        std::size_t bandAt[BlockMatrix<T>::kMaxBands + 1];
        for (std::size_t k = 0; k <= W.offsets.size(); ++k) bandAt[k] = 6 * k * W.stride + W.pad;
        T* half = levels[l].half.data();
        std::size_t halfAt[BlockMatrix<T>::kMaxBands + 1];  // band e's first array in `half`
        for (int e = 0; e < F.halfBands; ++e) halfAt[e] = 6 * std::size_t(e) * F.halfStride + F.halfPad;
        pool.run(ny, [&](int begin, int end) {
            T* out[BlockMatrix<T>::kMaxBands + 1];
            for (int y = begin; y < end; ++y) {
                for (int e = 0; e < F.halfBands; ++e) out[e] = half + halfAt[e] + y * cx;
                nestedGalerkinRow<T, 2>(F.nestedX.data(), int(F.nestedX.size()), W.values.data(), bandAt, W.stride, nx,
                                        ny, 1, cx, y, out, F.halfStride, F.halfBands);
            }
        });
        // Then y, row by coarse row. A banded coarse level gets its rows in place: band d of the
        // terms is band bandC[d] of C (-1: no such band; then no pair of the pattern has that
        // offset, and where a band's pair is off the grid, the terms sum to zero, as the band
        // holds); its block copy, where a plan reads it, from there. A gathered coarse level gets
        // its rows through G and put().
        int bandC[32];
        const bool direct = C.A.banded();
        for (int d = 0; d < bands; ++d) {
            const int o = D[d].second * cx + D[d].first;
            const auto it = std::lower_bound(C.A.offsets.begin(), C.A.offsets.end(), o);
            bandC[d] = d == 0 ? 0 : it != C.A.offsets.end() && *it == o ? 1 + int(it - C.A.offsets.begin()) : -1;
        }
        pool.run(cy, [&](int begin, int end) {
            std::vector<T> G(direct ? 0 : std::size_t(bands) * 6 * cx);
            T* out[32];
            for (int Y = begin; Y < end; ++Y) {
                for (int d = 0; d < bands; ++d)
                    out[d] = !direct ? &G[std::size_t(d) * 6 * cx]
                             : bandC[d] >= 0 ? &C.A.values[6 * std::size_t(bandC[d]) * C.A.stride + C.A.pad + Y * cx]
                                             : nullptr;
                const std::size_t outStride = direct ? C.A.stride : std::size_t(cx);
                nestedGalerkinRow<T, 1>(F.nestedY.data(), int(F.nestedY.size()), half, halfAt, F.halfStride, cx, ny,
                                        2, cx, Y, out, outStride, bands);
                if (direct && C.A.blocks.empty()) continue;  // nothing else holds the blocks
                for (int d = 0; d < bands; ++d)
                    for (int X = 0; out[d] && X < cx; ++X) {
                        const int dst = F.nestedDst[std::size_t(d) * nc + Y * cx + X];
                        if (dst < 0) continue;
                        T block[6];
                        for (int q = 0; q < 6; ++q) block[q] = out[d][q * outStride + X];
                        if (direct) std::copy(block, block + 6, &C.A.blocks[6 * std::size_t(dst)]);
                        else C.A.put(dst, block);
                    }
            }
        });
    } else {
        const int dsts = C.A.n + C.A.slots;
        pool.run(dsts, [&](int begin, int end) {
            for (int d = begin; d < end; ++d) {
                T acc[6] = {0, 0, 0, 0, 0, 0};
                for (int p = F.planStart[d]; p < F.planStart[d + 1]; ++p)
                    symAxpy(F.planW[p], W.block(F.planSrc[p]), acc);
                C.A.put(d, acc);
            }
        });
    }
    pool.run(C.A.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            T D[6];
            for (int q = 0; q < 6; ++q) D[q] = C.A.get(i, q);
            // A row that no unknown reaches (all of its fine points pinned) is empty.
            C.active[i] = (D[0] + D[3] + D[5]) != T(0) ? T(1) : T(0);
            symmetricInverse(D, &C.dinv[6 * std::size_t(i)]);
        }
    });
}

template <class T>
void Multigrid<T>::Impl::factorCoarsest() {
    const Level& L = levels.back();
    Eigen::MatrixXd M = L.A.dense();
    for (int i = 0; i < L.A.n; ++i)
        if (L.active[i] == T(0)) M.block<3, 3>(3 * i, 3 * i).setIdentity();
    coarsest.compute(M);
    useFallback = coarsest.info() != Eigen::Success;
    if (useFallback) coarsestFallback.compute(M);
}

// out = b - A x (b given), or out = A x (b null), rows [begin, end).
template <class T>
void blockProduct(const BlockMatrix<T>& A, const T* __restrict x, const T* __restrict b, T* __restrict out, int begin,
                  int end) {
    const int n = A.n;
    const int* __restrict start = A.start.data();
    const int* __restrict col = A.col.data();
    const int* __restrict slot = A.slot.data();
    const T* __restrict diag = A.values.data();
    const T* __restrict off = A.values.data() + 6 * std::size_t(n);  // gathered: block b at 6 b
    for (int i = begin; i < end; ++i) {
        const T* d = diag + 6 * std::size_t(i);
        const T* xi = x + 3 * std::size_t(i);
        T y0 = d[0] * xi[0] + d[1] * xi[1] + d[2] * xi[2];
        T y1 = d[1] * xi[0] + d[3] * xi[1] + d[4] * xi[2];
        T y2 = d[2] * xi[0] + d[4] * xi[1] + d[5] * xi[2];
        for (int e = start[i]; e < start[i + 1]; ++e) {
            const T* s = off + 6 * std::size_t(slot[e]);
            const T* xj = x + 3 * std::size_t(col[e]);
            const T q0 = xj[0], q1 = xj[1], q2 = xj[2];
            y0 += s[0] * q0 + s[1] * q1 + s[2] * q2;
            y1 += s[1] * q0 + s[3] * q1 + s[4] * q2;
            y2 += s[2] * q0 + s[4] * q1 + s[5] * q2;
        }
        T* o = out + 3 * std::size_t(i);
        if (b) {
            const T* bi = b + 3 * std::size_t(i);
            o[0] = bi[0] - y0, o[1] = bi[1] - y1, o[2] = bi[2] - y2;
        } else {
            o[0] = y0, o[1] = y1, o[2] = y2;
        }
    }
}

template <class T>
void Multigrid<T>::Impl::product(int l, const std::vector<T>& x, const std::vector<T>* b, std::vector<T>& out) {
    Level& L = levels[l];
    const BlockMatrix<T>& A = L.A;
    out.resize(x.size());
    const T* bp = b ? b->data() : nullptr;
    if (!A.banded()) {
        pool.run(A.n, [&](int begin, int end) { blockProduct(A, x.data(), bp, out.data(), begin, end); });
        return;
    }
    pool.run(A.n, [&](int begin, int end) {
        T* X = L.xs.data() + A.pad;
        for (int i = begin; i < end; ++i)
            for (int a = 0; a < 3; ++a) X[a * L.xStride + i] = x[3 * std::size_t(i) + a];
    });
    const T* X = L.xs.data() + A.pad;
    const bool springs = L.band.used();  // a cloth's level: its springs' blocks in compact form
    pool.run(A.n, [&](int begin, int end) {
        if (springs) springBandProduct(A, L.band, X, X + L.xStride, X + 2 * L.xStride, bp, out.data(), begin, end);
        else bandedProduct(A, X, X + L.xStride, X + 2 * L.xStride, bp, out.data(), begin, end);
    });
}

// Damped block Jacobi: x += omega W_ii^-1 (b - W x).
template <class T>
void Multigrid<T>::Impl::smooth(int l, bool residualKnown) {
    Level& L = levels[l];
    if (!residualKnown) residual(l, L.x, L.b, L.r);
    const T omega = T(settings.damping);
    pool.run(L.A.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            T d[3];
            symmetricTimes(&L.dinv[6 * std::size_t(i)], &L.r[3 * std::size_t(i)], d);
            for (int a = 0; a < 3; ++a) L.x[3 * std::size_t(i) + a] += omega * d[a];
        }
    });
}

// One cycle on level l for L.b from L.x (residualKnown: L.r already holds b - W x).
template <class T>
void Multigrid<T>::Impl::cycle(int l, bool residualKnown) {
    Level& L = levels[l];
    if (l + 1 == int(levels.size())) {
        Eigen::VectorXd b(3 * L.A.n);
        for (int q = 0; q < 3 * L.A.n; ++q) b[q] = double(L.b[q]) * double(L.active[q / 3]);
        const Eigen::VectorXd x = useFallback ? Eigen::VectorXd(coarsestFallback.solve(b)) : Eigen::VectorXd(coarsest.solve(b));
        for (int q = 0; q < 3 * L.A.n; ++q) L.x[q] = T(x[q]) * L.active[q / 3];
        return;
    }
    for (int s = 0; s < settings.preSweeps; ++s) smooth(l, s == 0 && residualKnown);
    if (settings.preSweeps > 0 || !residualKnown) residual(l, L.x, L.b, L.r);
    Level& C = levels[l + 1];
    const Transfer& P = L.P;
    pool.run(C.A.n, [&](int begin, int end) {  // b_c = P^T r; x_c = 0, so r_c = b_c
        for (int I = begin; I < end; ++I) {
            T acc[3];
            P.gather(false, I, L.r.data(), acc);
            for (int a = 0; a < 3; ++a) {
                C.b[3 * std::size_t(I) + a] = acc[a];
                C.r[3 * std::size_t(I) + a] = acc[a];
                C.x[3 * std::size_t(I) + a] = T(0);
            }
        }
    });
    coarseSolve(l + 1);
    pool.run(L.A.n, [&](int begin, int end) {  // x += P x_c on rows with an unknown
        for (int i = begin; i < end; ++i) {
            T acc[3];
            P.gather(true, i, C.x.data(), acc);
            for (int a = 0; a < 3; ++a) L.x[3 * std::size_t(i) + a] += L.active[i] * acc[a];
        }
    });
    for (int s = 0; s < settings.postSweeps; ++s) smooth(l, false);
}

// Level l's x from its b (with r = b, x = 0): one cycle, or on a K-cycle level (1..kLevels(), not
// the coarsest) two iterations of flexible CG, each preconditioned by one cycle: c1 = B b, then
// c2 = B (b - t1 W c1), and x the combination of c1 and c2 that minimizes the W-norm of the error
// over their span. Level 0 is always one cycle (the outer CG is its Krylov method).
template <class T>
void Multigrid<T>::Impl::coarseSolve(int l) {
    Level& C = levels[l];
    if (l == 0 || l > settings.kLevels() || l + 1 == int(levels.size())) return cycle(l, true);
    C.kb = C.b;
    cycle(l, true);
    C.kc = C.x;
    product(l, C.kc, nullptr, C.kq);
    const double rho1 = dot(C.kc, C.kq);
    if (!(rho1 > 0)) return;  // c1 = 0: b = 0, and x = c1
    const double t1 = dot(C.kc, C.kb) / rho1;
    const T t1T = T(t1);
    pool.run(C.A.n, [&](int begin, int end) {
        for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q) {
            C.b[q] = C.r[q] = C.kb[q] - t1T * C.kq[q];
            C.x[q] = T(0);
        }
    });
    cycle(l, true);
    product(l, C.x, nullptr, C.kq2);
    const double gamma = dot(C.x, C.kq), beta = dot(C.x, C.kq2), alpha2 = dot(C.x, C.b);
    const double rho2 = beta - gamma * gamma / rho1;
    const bool second = rho2 > 1e-12 * beta;  // else c2 adds nothing independent of c1
    const T w1 = T(second ? t1 - gamma * alpha2 / (rho1 * rho2) : t1), w2 = T(second ? alpha2 / rho2 : 0.0);
    pool.run(C.A.n, [&](int begin, int end) {
        for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q) C.x[q] = w1 * C.kc[q] + w2 * C.x[q];
    });
}

template <class T>
double Multigrid<T>::Impl::dot(const std::vector<T>& a, const std::vector<T>& b) {
    const int n = int(a.size() / 3);
    partial.assign(chunks(n), 0.0);
    pool.run(chunks(n), [&](int begin, int end) {
        for (int ch = begin; ch < end; ++ch) {
            const std::size_t first = 3 * std::size_t(ch) * kChunk;
            const std::size_t last = std::min(a.size(), 3 * std::size_t(ch + 1) * kChunk);
            partial[ch] = laneDot(a.data() + first, b.data() + first, last - first);
        }
    });
    double s = 0;
    for (double p : partial) s += p;
    return s;
}

template <class T>
double Multigrid<T>::Impl::norm(const std::vector<T>& v) {
    return std::sqrt(dot(v, v));
}

// The adaptive stop: |r| / |b| (rel) at most the tolerance and, with a local tolerance, no
// particle's Jacobi correction |W_ii^-1 r_i| above it times the largest |x_i|. The maxima do not
// depend on the order of the chunks, so any thread count gives the same answer.
template <class T>
bool Multigrid<T>::Impl::converged(double rel, const std::vector<T>& r, const std::vector<T>& x) {
    if (rel > settings.tolerance) return false;
    if (settings.localTolerance <= 0) return true;
    const Level& L = levels[0];
    const int n = L.A.n;
    auto squared = [](const T* v) { return double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]; };
    partial.assign(2 * std::size_t(chunks(n)), 0.0);
    pool.run(chunks(n), [&](int begin, int end) {
        for (int ch = begin; ch < end; ++ch) {
            double correction = 0, dv = 0;
            for (int i = ch * kChunk; i < std::min(n, (ch + 1) * kChunk); ++i) {
                T d[3];
                symmetricTimes(&L.dinv[6 * std::size_t(i)], &r[3 * std::size_t(i)], d);
                correction = std::max(correction, squared(d));
                dv = std::max(dv, squared(&x[3 * std::size_t(i)]));
            }
            partial[2 * std::size_t(ch)] = correction;
            partial[2 * std::size_t(ch) + 1] = dv;
        }
    });
    double correction = 0, dv = 0;
    for (std::size_t ch = 0; ch < partial.size(); ch += 2)
        correction = std::max(correction, partial[ch]), dv = std::max(dv, partial[ch + 1]);
    const double t = settings.localTolerance;
    return correction <= t * t * dv;
}

template <class T>
void Multigrid<T>::Impl::precondition(const std::vector<T>& r, std::vector<T>& z) {
    auto cycleOn = [&](auto& h) {  // this hierarchy, or its float copy (r rounded to float)
        auto& L = h.levels[0];
        using U = typename std::decay_t<decltype(L.x)>::value_type;
        z.resize(r.size());
        pool.run(L.A.n, [&](int begin, int end) {
            for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q)
                L.b[q] = L.r[q] = U(r[q]), L.x[q] = U(0);
        });
        h.cycle(0, true);
        pool.run(L.A.n, [&](int begin, int end) {
            for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q) z[q] = T(L.x[q]);
        });
    };
    if (lower) cycleOn(*lower);
    else cycleOn(*this);
}

namespace {

// The coefficients c that minimize the energy norm of the error of x = sum_j c_j p_j, from the
// Gram matrix G_ij = p_i . W p_j and g_i = p_i . b: G c = g, by Cholesky with the vectors taken in
// order (newest first), and a vector dropped (c_j = 0) when what it adds beyond the ones kept has
// at most `drop` of its own energy (a vector the others nearly span would only amplify rounding).
Eigen::VectorXd energyCoefficients(const Eigen::MatrixXd& G, const Eigen::VectorXd& g, double drop) {
    const int k = int(g.size());
    std::vector<int> kept;
    Eigen::MatrixXd L = Eigen::MatrixXd::Zero(k, k);  // Cholesky factor of G over the kept vectors
    auto over = [&](const Eigen::VectorXd& v) {  // v's entries of the kept vectors
        Eigen::VectorXd o(kept.size());
        for (std::size_t a = 0; a < kept.size(); ++a) o[a] = v[kept[a]];
        return o;
    };
    for (int j = 0; j < k; ++j) {
        const int m = int(kept.size());
        const Eigen::VectorXd row = L.topLeftCorner(m, m).triangularView<Eigen::Lower>().solve(over(G.col(j)));
        const double pivot = G(j, j) - row.squaredNorm();
        if (!(pivot > drop * G(j, j))) continue;
        L.row(m).head(m) = row.transpose();
        L(m, m) = std::sqrt(pivot);
        kept.push_back(j);
    }
    const int m = int(kept.size());
    const auto Lk = L.topLeftCorner(m, m).triangularView<Eigen::Lower>();
    const Eigen::VectorXd ck = Lk.transpose().solve(Lk.solve(over(g)));
    Eigen::VectorXd c = Eigen::VectorXd::Zero(k);
    for (int a = 0; a < m; ++a) c[kept[a]] = ck[a];
    return c;
}

}  // namespace

// The iteration's start x and its residual r = b - W x (b: level 0's); returns |r| / |b|. From
// zero, or (MultigridSettings::start) from the combination of the last solves' dv (on the rows
// free now) that minimizes the energy norm of the error, ||x - x*||_W, over their span: one
// product with W per vector, a small Gram system, and r from the products, with no product more.
// The span holds the previous dv itself, so the start is never worse in that norm than it; with
// two vectors it holds the linear extrapolation 2 dv_{n-1} - dv_{n-2} too. Nor is it worse than
// zero (after a jump or a change of pins the coefficients go to nearly nothing).
template <class T>
double Multigrid<T>::Impl::start(std::vector<T>& x, std::vector<T>& r, double bNorm) {
    Level& L = levels[0];
    int k = 0;
    while (warmStart() && k < int(history.size()) && history[k].size() == L.b.size()) ++k;
    if (k > 0) {
        historyW.resize(k);
        Eigen::MatrixXd G(k, k);
        Eigen::VectorXd g(k);
        for (int j = 0; j < k; ++j) {
            T* p = history[j].data();
            pool.run(L.A.n, [&](int begin, int end) {
                for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q) p[q] *= L.active[q / 3];
            });
            product(0, history[j], nullptr, historyW[j]);
            g[j] = dot(history[j], L.b);
            for (int i = 0; i <= j; ++i) G(i, j) = G(j, i) = dot(history[i], historyW[j]);
        }
        // float: keep the coefficients small enough that the rounding of r stays far below the
        // tolerances a float solve reaches
        const Eigen::VectorXd c = energyCoefficients(G, g, std::is_same_v<T, float> ? 1e-5 : 1e-10);
        x.assign(L.b.size(), T(0));
        r = L.b;
        for (int j = 0; j < k; ++j) {
            const T cj = T(c[j]);
            if (cj == T(0)) continue;
            const T *p = history[j].data(), *q = historyW[j].data();
            pool.run(L.A.n, [&](int begin, int end) {
                for (std::size_t e = 3 * std::size_t(begin); e < 3 * std::size_t(end); ++e)
                    x[e] += cj * p[e], r[e] -= cj * q[e];
            });
        }
        return norm(r) / bNorm;
    }
    x.assign(L.b.size(), T(0));
    r = L.b;
    return 1;
}

// Cycles as a stationary iteration on W x = b (L.b), from start().
template <class T>
void Multigrid<T>::Impl::stationary(double bNorm, MultigridStats& stats) {
    Level& L = levels[0];
    const MultigridSettings& s = settings;
    double rel = start(L.x, L.r, bNorm);
    const bool adaptive = s.cycles == 0;
    const int cap = adaptive ? s.maxCycles : s.cycles;
    while (stats.cycles < cap && (!adaptive || !converged(rel, L.r, L.x))) {
        cycle(0, true);
        ++stats.cycles;
        // The next cycle (if any) and the adaptive test need the residual; the last fixed one not.
        if (adaptive || stats.cycles < cap) residual(0, L.x, L.b, L.r);
        if (adaptive) rel = norm(L.r) / bNorm;
    }
    stats.residual = adaptive ? rel : -1;
    cgX = L.x;
}

// Conjugate gradients preconditioned by one cycle per iteration, from start(); the result in cgX.
template <class T>
void Multigrid<T>::Impl::conjugateGradients(double bNorm, MultigridStats& stats) {
    const MultigridSettings& s = settings;
    double rel = start(cgX, cgR, bNorm);
    const bool adaptive = s.cycles == 0;
    const int cap = adaptive ? s.maxCycles : s.cycles;
    double rz = 0, alpha = 0;
    while (stats.cycles < cap && (!adaptive || !converged(rel, cgR, cgX))) {
        precondition(cgR, cgZ);
        ++stats.cycles;
        const double rzNext = dot(cgR, cgZ);
        if (stats.cycles == 1) cgP = cgZ;
        else {
            // A K-cycle is not a fixed linear operator, nor quite is a cycle in float (it rounds):
            // the flexible beta z.(r - r_last) / rz, with r - r_last = -alpha W p_last (in cgQ),
            // keeps the directions conjugate.
            const bool flexible = s.kLevels() > 0 || lower;
            const T beta = T(flexible ? -alpha * dot(cgZ, cgQ) / rz : rzNext / rz);
            for (std::size_t q = 0; q < cgP.size(); ++q) cgP[q] = cgZ[q] + beta * cgP[q];
        }
        rz = rzNext;
        product(0, cgP, nullptr, cgQ);  // q = W p
        const double pq = dot(cgP, cgQ);
        if (!(pq > 0)) break;  // W p = 0 only for p = 0: converged to rounding
        alpha = rz / pq;
        const T a = T(alpha);
        for (std::size_t q = 0; q < cgX.size(); ++q) cgX[q] += a * cgP[q], cgR[q] -= a * cgQ[q];
        if (adaptive) rel = norm(cgR) / bNorm;
    }
    stats.residual = adaptive ? rel : -1;
}

template <class T>
Multigrid<T>::Multigrid(const MultigridSettings& settings, std::shared_ptr<ThreadPool> pool)
    : impl_(std::make_unique<Impl>(settings, std::move(pool))) {}

template <class T>
Multigrid<T>::~Multigrid() = default;

template <class T>
void Multigrid<T>::prepareSystem(const Model& model, const Environment& env, const State& state, const StepInput& input,
                                 bool compressionRule) {
    Impl& m = *impl_;
    if (m.modelId != model.id()) m.prepare(model);
    m.buildFine(model, env, state, input, compressionRule);
    if constexpr (std::is_same_v<T, double>) {
        if (!m.lower) return;
        if (m.lower->modelId != model.id()) m.lower->prepare(model);
        m.lower->roundFine(m);
    }
}

template <class T>
bool Multigrid<T>::solve(const Model& model, const Environment& env, const State& state, const StepInput& input,
                         bool compressionRule, Points& dv, MultigridStats& stats, double* forcesMs) {
    const auto t0 = std::chrono::steady_clock::now();
    prepareSystem(model, env, state, input, compressionRule);
    if (forcesMs) *forcesMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    Impl& m = *impl_;
    if (m.lower) m.lower->refreshCoarse(m.lower->lastH2, m.lower->lastCompression);  // the cycles' levels
    else m.refreshCoarse(m.lastH2, m.lastCompression);

    typename Impl::Level& L = m.levels[0];
    const int n = L.A.n;
    const double bNorm = m.norm(L.b);
    stats = {};
    if (bNorm > 0) {
        if (m.settings.conjugateGradients()) m.conjugateGradients(bNorm, stats);
        else m.stationary(bNorm, stats);
    } else {
        m.cgX.assign(L.b.size(), T(0));
        stats.residual = 0;
    }
    dv.resize(3, n);
    double* out = dv.data();
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
            out[3 * i + a] = L.pinned[i] ? double(m.pinDv[3 * i + a]) : double(m.cgX[3 * std::size_t(i) + a]);
    if (m.warmStart()) {
        if (int(m.history.size()) < m.settings.startHistory) m.history.emplace_back();
        std::rotate(m.history.rbegin(), m.history.rbegin() + 1, m.history.rend());
        m.history[0].swap(m.cgX);  // the next start() rewrites cgX
    }
    return dv.allFinite();
}

template <class T>
int Multigrid<T>::levels() const {
    return int(impl_->levels.size());
}

template <class T>
const BlockMatrix<T>& Multigrid<T>::matrix(int level) const {
    return impl_->levels[level].A;
}

template <class T>
Eigen::MatrixXd Multigrid<T>::prolongation(int level) const {
    const Transfer& P = impl_->levels[level].P;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(3 * P.fine, 3 * P.coarse);
    for (int i = 0; i < P.fine; ++i)
        for (int e = P.pStart[i]; e < P.pStart[i + 1]; ++e)
            for (int a = 0; a < 3; ++a) M(3 * i + a, 3 * P.pCol[e] + a) = P.pW[e];
    return M;
}

template <class T>
Eigen::VectorXd Multigrid<T>::vcycle(const Eigen::VectorXd& b) {
    return coarseSolve(0, b);
}

template <class T>
Eigen::VectorXd Multigrid<T>::coarseSolve(int level, const Eigen::VectorXd& b) {
    Impl& m = *impl_;
    m.coarseAge = -1;  // built now, for the system prepareSystem made, and recorded as such for solve()
    m.refreshCoarse(m.lastH2, m.lastCompression);
    typename Impl::Level& L = m.levels[level];
    for (int q = 0; q < 3 * L.A.n; ++q) L.b[q] = T(b[q]) * L.active[q / 3], L.x[q] = T(0);
    L.r = L.b;
    m.coarseSolve(level);
    Eigen::VectorXd x(3 * L.A.n);
    for (int q = 0; q < 3 * L.A.n; ++q) x[q] = double(L.x[q]);
    return x;
}

template <class T>
std::string Multigrid<T>::describeHierarchy() const {
    return impl_->coarseningName + (impl_->lower ? ", cycles in float" : "");
}

template struct BlockMatrix<float>;
template struct BlockMatrix<double>;
template class Multigrid<float>;
template class Multigrid<double>;

}  // namespace cloth
