#pragma once
// The finest level of a cloth whose springs cannot be banded (a mesh): the springs one by one,
// and W and b gathered row by row from them.

#include <vector>

#include "cloth/model.h"
#include "cloth/thread_pool.h"
#include "fine_inputs.h"
#include "level.h"

namespace cloth {

template <class T>
struct SpringSet {
    std::vector<int> si, sj, adjSpring;
    std::vector<T> k, rest, adjSign;  // adjSign: +1 where the row is the spring's i end
    std::vector<T> bterm;
    std::vector<T> pinnedJ;  // 6 per spring, written only for a spring with a pinned end

    void assign(const Model& m);
    // Eqs. 15-17 at positions xs, once per spring. Each spring's block of W, -h^2 J, goes to W's
    // slot s (zero where an end is pinned, and then J to pinnedJ, for the free end's diagonal); its
    // term of b for the row of its i end, h fm u + h^2 J (v_j - v_i), goes to bterm[3 s] (the j
    // end's is the negative).
    void compute(const FineInputs<T>& in, BlockMatrix<T>& W, ThreadPool& pool);
};

// W and b of level 0 from the springs' blocks (SpringSet::compute): W_ii = base_i + h^2 sum_j J_ij
// (eq. 12); rows and columns of pinned particles are zero. b_i = the sum of its springs' terms +
// h^2 J_ij dv_j for each pinned neighbour j (its prescribed change, eq. 7) + the row's forces.
template <class T>
void assembleGathered(const SpringSet<T>& S, const FineInputs<T>& in, Level<T>& L, ThreadPool& pool);

}  // namespace cloth
