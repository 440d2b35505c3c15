#pragma once
// The Galerkin product W_c = P^T W P: the coarse pattern, and a plan computed once per model that
// says which fine block, with which weight, lands in which coarse block. On nested grids the
// product runs by stencil instead (nested_galerkin.h).

#include <vector>

#include "block_matrix.h"
#include "cloth/thread_pool.h"
#include "nested_galerkin.h"
#include "transfer.h"

namespace cloth {

// The coarse pattern of P^T W P (blocks (I, J) reached by some fine block (i, j) with
// P_iI P_jJ != 0), with one slot per pair.
template <class T>
void galerkinPattern(const BlockMatrix<T>& fine, const Transfer& P, BlockMatrix<T>& coarse);

template <class T>
struct GalerkinPlan {
    // Coarse block d gets sum over [start[d], start[d+1]) of w * the fine block src.
    std::vector<int> start, src;
    std::vector<T> w;

    bool empty() const { return start.empty(); }
    // The plan for `coarse`, whose pattern is set (galerkinPattern).
    void build(const BlockMatrix<T>& fine, const Transfer& P, const BlockMatrix<T>& coarse);
    // coarse's blocks from fine's (fine gathered, or banded with its block copy).
    void apply(const BlockMatrix<T>& fine, BlockMatrix<T>& coarse, ThreadPool& pool) const;
};

}  // namespace cloth
