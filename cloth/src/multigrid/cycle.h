#pragma once
// Relaxation and the cycle. One cycle on level l: nu1 damped block-Jacobi sweeps (the paper's
// eq. 11 sweep, damped by omega), r = b - W x, b_c = P^T r, the coarse solve (recursively),
// x += P x_c, nu2 sweeps; the coarsest level is solved directly. A K-cycle level (1..kLevels,
// not the coarsest) makes its coarse solve two flexible CG iterations, each preconditioned by one
// cycle from there (Notay and Vassilevski's K-cycle).

#include <vector>

#include "hierarchy.h"
#include "reductions.h"

namespace cloth {

struct CycleOptions {
    int preSweeps = 1, postSweeps = 1;  // smoothing sweeps around each coarse correction
    double damping = 0.7;               // smoother: x += damping W_ii^-1 r
    int kcycleLevels = 1;               // levels 1..N are K-cycles; 0: V-cycles
};

template <class T>
class Cycle {
public:
    Cycle(const CycleOptions& options, Reductions& sums) : options_(options), sums_(sums) {}

    // One cycle on level l for its b from its x (residualKnown: its r already holds b - W x).
    void run(Hierarchy<T>& h, int l, bool residualKnown);
    // Level l's x from its b (with r = b, x = 0): one cycle, or on a K-cycle level two flexible
    // CG iterations, each preconditioned by one. Level 0 is always one cycle.
    void coarseSolve(Hierarchy<T>& h, int l);
    // z = one cycle from zero on level 0 for the right-hand side r (rounded to T).
    template <class U>
    void precondition(Hierarchy<T>& h, const std::vector<U>& r, std::vector<U>& z);
    // Whether the cycle is a fixed linear operator (no K-cycle levels).
    bool linear() const { return options_.kcycleLevels <= 0; }

private:
    void smooth(Hierarchy<T>& h, int l, bool residualKnown);
    void restrictResidual(Hierarchy<T>& h, int l);
    void prolongCorrection(Hierarchy<T>& h, int l);
    CycleOptions options_;
    Reductions& sums_;
};

extern template class Cycle<float>;
extern template class Cycle<double>;

}  // namespace cloth
