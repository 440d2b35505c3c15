#pragma once
// Where each solve starts: from the combination of the last solves' dv (on the rows free now)
// that minimizes the energy norm of the error, ||x - x*||_W, over their span: one product with W
// per vector, a small Gram system, and r from the products, with no product more. The span holds
// the previous dv itself, so the start is never worse in that norm than it; with two vectors it
// holds the linear extrapolation 2 dv_{n-1} - dv_{n-2} too. Nor is it worse than zero (after a
// jump or a change of pins the coefficients go to nearly nothing).

#include <vector>

#include "hierarchy.h"
#include "reductions.h"

namespace cloth {

template <class T>
class WarmStart {
public:
    // history: how many past solves to combine (0: every solve starts from zero).
    explicit WarmStart(int history) : size_(history) {}
    // x and r = b - W x for level 0's system; returns |r| / |b|.
    double start(Hierarchy<T>& h, Reductions& sums, double bNorm, std::vector<T>& x, std::vector<T>& r);
    // Keeps x (taken by swap: the next start rewrites it) as the newest past solve.
    void remember(std::vector<T>& x);
    void clear() { history_.clear(); }

private:
    int size_;
    std::vector<std::vector<T>> history_;   // newest first
    std::vector<std::vector<T>> historyW_;  // scratch: W times each
};

extern template class WarmStart<float>;
extern template class WarmStart<double>;

}  // namespace cloth
