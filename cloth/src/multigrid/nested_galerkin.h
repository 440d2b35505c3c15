#pragma once
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
// of 109 at once.)

#include <vector>

#include "block_matrix.h"
#include "cloth/thread_pool.h"

namespace cloth {

template <class T>
struct NestedTerm {
    int dst = 0;    // output band (0: the diagonal): the intermediate grid's, or nestedOffsets()' order
    int band = 0;   // source band holding W(i, i + o) (0: the diagonal)
    int ax = 0, ay = 0;
    int shift = 0;  // the block's source row: i (o in the upper half) or i + o (lower half: W_ji = W_ij)
    T w = 0;
};

template <class T>
struct NestedGalerkin {
    // x coarsens the fine rows into the intermediate grid cx x ny, whose blocks go to `half`
    // (band e's six arrays at half[(6 e + q) * halfStride + halfPad]); y then the intermediate rows
    // into the coarse rows. dst: where each coarse (band, row) lands, its destination block (the
    // diagonal I, or n_c + slot), -1 where the pair is off the coarse grid.
    std::vector<NestedTerm<T>> x, y;
    int halfBands = 0, halfPad = 0;
    std::size_t halfStride = 0;
    std::vector<T> half;
    int gridNx = 0, gridNy = 0;
    std::vector<int> dst;

    bool empty() const { return x.empty(); }
    // The terms for `fine` (an nx x ny grid) and `coarse`, whose pattern is set; false (use the
    // plan) unless both sides are odd and at least 5, the coarse rows are at least minRow long,
    // `fine` will be banded, every band is a 2D offset within 2 points, and the terms reach every
    // coarse entry.
    bool build(const BlockMatrix<T>& fine, const BlockMatrix<T>& coarse, int nx, int ny, int minRow);
    // coarse's blocks (banded in place, else through put()) from fine's bands.
    void apply(const BlockMatrix<T>& fine, BlockMatrix<T>& coarse, ThreadPool& pool);
};

}  // namespace cloth
