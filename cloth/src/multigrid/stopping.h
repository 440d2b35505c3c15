#pragma once
// The adaptive stop: |r| / |b| at most the tolerance and, with a local tolerance, no particle's
// Jacobi correction |W_ii^-1 r_i| above it times the largest |x_i|. The relative residual is a
// mean over the cloth: a wave front whose error sits on a few hundred particles passes it, and the
// error it leaves there seeds a stretch spike a few steps later; the local test catches it.

#include <vector>

#include "level.h"
#include "reductions.h"

namespace cloth {

struct StoppingTest {
    double tolerance = 1.5e-3;
    double localTolerance = 1e-2;  // 0: the relative residual alone

    // rel = |r| / |b|; L0 gives W_ii^-1. The maxima do not depend on the order of the chunks, so
    // any thread count gives the same answer.
    template <class T>
    bool converged(double rel, const std::vector<T>& r, const std::vector<T>& x, const Level<T>& L0,
                   Reductions& sums) const;
};

}  // namespace cloth
