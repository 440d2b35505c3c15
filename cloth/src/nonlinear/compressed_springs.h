#pragma once
// What eq. 17 leaves out of the exact Newton matrix: on every compressed spring (L < l0),
//   J - J_17 = k (1 - l0/L) (I - u u^T) = dJ.
// The exact product subtracts h^2 dJ (x_j - x_i) from row i and adds it to row j. On one thread
// that is one pass over the compressed springs in their order. On more, each spring's term is
// computed once, then each row gathers its springs' terms in the springs' order: every row adds
// the same numbers in the same order, so the bits do not depend on the thread count.

#include <cstdint>
#include <vector>

#include "cloth/model.h"
#include "cloth/thread_pool.h"

namespace cloth {

class CompressedSprings {
public:
    // The compressed springs of `model` at positions x.
    void build(const Model& model, const Points& x, ThreadPool& pool);
    void clear();
    bool empty() const { return springs_.empty(); }
    // y -= scale (J - J_17) x on the rows of the unpinned particles; x and y are 3n particle-major.
    void subtract(const double* x, Scalar scale, const std::vector<std::uint8_t>& pinned, double* y,
                  ThreadPool& pool);

private:
    struct Entry {
        Index i, j;
        Mat3 dJ;
    };
    void collect(const Model& model, const Points& x, ThreadPool& pool);
    void listByParticle(Index n);
    Vec3 term(const Entry& e, const double* x, Scalar scale) const;

    std::vector<Entry> springs_;
    // With more than one thread: each spring's term, and of_[start_[p] .. start_[p + 1]) p's
    // compressed springs c, as 2 c when p is c's first end, 2 c + 1 when its second.
    std::vector<Vec3> d_;
    std::vector<Index> start_, of_;
    std::vector<Mat3> all_;  // collect()'s scratch: one per spring
    std::vector<std::uint8_t> isCompressed_;
};

}  // namespace cloth
