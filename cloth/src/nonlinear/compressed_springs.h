#pragma once
// What eq. 17 leaves out of the exact Newton matrix: on every compressed spring (L < l0),
//   J - J_17 = k (1 - l0/L) (I - u u^T) = dJ.
// The exact product subtracts h^2 dJ (x_j - x_i) from row i and adds it to row j. Kept in the
// springs' order with each particle's compressed springs listed in that order, so that the
// product is one pass over the springs and one over the particles, both split among a pool's
// threads, and each row adds its terms in the order of a single loop over the springs: the same
// bits for any thread count.

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
    // d_s = scale dJ_s (x_j - x_i) for every compressed spring s; x is 3n particle-major.
    void differences(const double* x, Scalar scale, ThreadPool& pool);
    // Row p of the product: y_p -= d_s where p is the spring's first end, += where its second,
    // over p's compressed springs in the springs' order (after differences()).
    void subtractAt(Index p, double* y) const;

private:
    struct Entry {
        Index i, j;
        Mat3 dJ;
    };
    std::vector<Entry> springs_;
    std::vector<Vec3> d_;
    std::vector<Index> start_, of_;  // of_[start_[p] .. start_[p + 1]): p's compressed springs
    std::vector<Entry> all_;         // build()'s scratch: one per spring
    std::vector<std::uint8_t> isCompressed_;
};

}  // namespace cloth
