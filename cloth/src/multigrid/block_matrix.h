#pragma once
// Block storage and products: a sparse symmetric matrix of symmetric 3x3 blocks, the operator
// every level of the hierarchy holds.

#include <Eigen/Dense>
#include <algorithm>
#include <cstddef>
#include <vector>

namespace cloth {

// A sparse symmetric matrix of symmetric 3x3 blocks (6 numbers each: xx xy xz yy yz zz).
// Row i's off-diagonal entries are e in [start[i], start[i + 1]), in column col[e], with their block
// in slot[e]: W_ij = W_ji, so the two entries of a pair share one slot (on level 0, a slot is a
// spring). Block b (b < n: the diagonal block of row b; b = n + s: slot s) keeps its six numbers at
// values[at[b] + q * stride], q = 0..5, in one of two layouts:
//   gathered  block after block (stride 1);
//   banded    for a matrix with few distinct column offsets j - i (a grid cloth has 6 in row-major
//             order: 1, 2, nx - 1, nx, nx + 1, 2 nx; its Galerkin coarse grids 12): by diagonals.
//             Band k holds W_{i, i + o_k} (o_0 = 0, then the offsets o_k > 0) of every row i as six
//             arrays over rows, zero where the row has no such entry, so that a product runs down
//             the bands and vectorizes over rows; W_{i, i - o} = W_{i - o, i} reads the same arrays
//             shifted (rows -pad .. -1 of every array are zero). Where a Galerkin plan reads the
//             level, the blocks are kept a second time, block after block (`blocks`): the plan
//             visits them by index, and there a block's six numbers share a cache line instead of
//             lying in six arrays.
template <class T>
struct BlockMatrix {
    static constexpr int kMaxBands = 24;
    int n = 0, slots = 0;
    std::vector<int> start, col, slot;
    std::vector<T> values;
    std::vector<T> blocks;        // banded and read by a plan: block b's six numbers again at 6 b (else empty)
    std::vector<std::size_t> at;  // n + slots
    std::size_t stride = 1;
    std::vector<int> offsets;     // banded: o_1 < o_2 < ...; empty: gathered
    int pad = 0;

    int entries() const { return int(col.size()); }
    // The entry of (i, j) in row i's sorted columns, or -1 if the pattern has none.
    int entryOf(int i, int j) const {
        const auto b = col.begin() + start[i], e = col.begin() + start[i + 1];
        const auto it = std::lower_bound(b, e, j);
        return it != e && *it == j ? int(it - col.begin()) : -1;
    }
    bool banded() const { return !offsets.empty(); }
    // The band holding offset o (0: the diagonal band).
    int bandOf(int o) const {
        return o == 0 ? 0 : 1 + int(std::lower_bound(offsets.begin(), offsets.end(), o) - offsets.begin());
    }
    // Array q of band k, at row 0 (banded).
    T* bandArray(int k, int q) { return values.data() + (6 * std::size_t(k) + q) * stride + pad; }
    const T* bandArray(int k, int q) const { return values.data() + (6 * std::size_t(k) + q) * stride + pad; }
    // The pattern's distinct column offsets j - i > 0 if it can be banded (one entry per row and
    // column, at most kMaxBands offsets, n >= 64), else empty.
    std::vector<int> bandOffsets() const;
    // Chooses the layout (banded where the pattern allows and allowBands; with the block copy if
    // keepBlocks) and zeroes the values.
    void layout(bool allowBands, bool keepBlocks);
    // One slot per pair (i < j), shared with (j, i), for the pattern in start and col.
    void numberSlots();
    // Or band-major for the band offsets o_1 < o_2 < ... (bandOffsets()): slot k n + i for the pair
    // (i, i + o_{k+1}), holes included, so that the block copy of a band is contiguous
    // (copyBandsToBlocks).
    void numberSlotsByBand(const std::vector<int>& bandOffsets);
    // Banded with band-major slots and the block copy kept: rows [begin, end) of every band into
    // the copy.
    void copyBandsToBlocks(int begin, int end);
    // Block b's six numbers, contiguous (gathered, or banded with the block copy).
    const T* block(int b) const { return banded() ? &blocks[6 * std::size_t(b)] : &values[6 * std::size_t(b)]; }
    T get(int b, int q) const { return values[at[b] + q * stride]; }
    // Sets block b (in the layout, and in `blocks` when kept).
    void put(int b, const T* v) {
        T* o = &values[at[b]];
        for (int q = 0; q < 6; ++q) o[q * stride] = v[q];
        if (!blocks.empty()) std::copy(v, v + 6, &blocks[6 * std::size_t(b)]);
    }
    Eigen::MatrixXd dense() const;  // for tests
};

// Array lengths in the banded layout are rounded to whole 4 KiB pages plus one cache line, so that
// the arrays a product streams through start in different cache sets (a whole number of pages
// apart, the 42 arrays of level 0 compete for a few sets and evict each other: a 1.5x slower step).
template <class T>
std::size_t spacedLength(std::size_t len) {
    constexpr std::size_t page = 4096 / sizeof(T), line = 64 / sizeof(T);
    return (len + page - 1) / page * page + line;
}

// out = b - W x (b given) or W x, rows [begin, end), for a banded W; x as three arrays X0, X1, X2
// with W.pad zeros before and after.
template <class T>
void bandedProduct(const BlockMatrix<T>& W, const T* X0, const T* X1, const T* X2, const T* b, T* out, int begin,
                   int end);
// The same for a gathered W, x interleaved (3n).
template <class T>
void blockProduct(const BlockMatrix<T>& A, const T* x, const T* b, T* out, int begin, int end);

extern template struct BlockMatrix<float>;
extern template struct BlockMatrix<double>;

}  // namespace cloth
