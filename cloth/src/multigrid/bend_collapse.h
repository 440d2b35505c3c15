#pragma once
// S = W with its bend springs collapsed, the operator the Galerkin product reads on level 0 of a
// grid. A bend spring (i, j = i + 2 d) with block O = W_ij and midpoint m = i + d is replaced by
// two springs (i, m), (m, j) with block 2 O each: the same energy for a displacement linear from
// i to j, so the coarse levels still see the bend springs' share of the stretching stiffness, and
// P^T S P keeps the 9-point stencil of S (P^T W P has 25 points: a bend spring from an odd point
// reaches two coarse points away). As a change of W:
//   W_ij -= O (to zero), W_im += 2 O, W_mj += 2 O, W_ii -= O, W_jj -= O, W_mm -= 4 O,
// then rows and columns of pinned particles are zero again. (A bend spring with a pinned end has
// O = 0 and is already on its free end's diagonal.) S is symmetric positive definite where W is:
// each collapsed spring is a spring with twice the block. The fine level keeps the true W
// (smoother, residual, CG); only the coarse operators change.

#include "banded_springs.h"
#include "block_matrix.h"
#include "cloth/thread_pool.h"

namespace cloth {

// S's pattern (A's without its bend springs), band-major; false (nothing collapsed) unless A is a
// banded grid (nx >= 5) whose bands are the structural (1, nx), shear (nx - 1, nx + 1) and bend
// (2, 2 nx) offsets, with both bend bands, and every bend spring's two halves are pairs of A.
template <class T>
bool collapsePattern(const BlockMatrix<T>& A, const BandedSprings<T>& springs, int nx, BlockMatrix<T>& S);

// S's values from A's (both laid out), with the free-row mask of the springs.
template <class T>
void collapseBends(const BlockMatrix<T>& A, const BandedSprings<T>& springs, int nx, BlockMatrix<T>& S,
                   ThreadPool& pool);

}  // namespace cloth
