#pragma once
// One level of the hierarchy: its operator, its vectors, its transfer to the next coarser level
// and how that level's operator is built from this one.

#include <vector>

#include "block_matrix.h"
#include "galerkin.h"
#include "transfer.h"

namespace cloth {

template <class T>
struct BandedSprings;

template <class T>
struct Level {
    BlockMatrix<T> A;
    // Level 0 of a banded cloth: the springs' blocks in compact form, which its product reads.
    const BandedSprings<T>* springs = nullptr;
    std::vector<T> xs;  // banded A: x as three arrays of xStride with A.pad zeros on both sides
    std::size_t xStride = 0;
    std::vector<T> dinv, active;     // 6n; 1 for a row with an unknown, 0 for a pinned (empty) one
    std::vector<T> x, b, r;          // 3n
    std::vector<T> kb, kc, kq, kq2;  // K-cycle levels: the right-hand side, c1, W c1, W c2
    Transfer P;                      // to the next coarser level (unused on the last)
    GalerkinPlan<T> plan;            // the next level's blocks from this one's, block by block
    NestedGalerkin<T> nested;        // or, on nested grids, by stencil
    // Level 0 of a grid with its bend springs collapsed (bend_collapse.h; the grid's nx, else 0):
    // the Galerkin product reads S instead of A.
    int bendNx = 0;
    BlockMatrix<T> S;
    const BlockMatrix<T>& source() const { return bendNx ? S : A; }
};

}  // namespace cloth
