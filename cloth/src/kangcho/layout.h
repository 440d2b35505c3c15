#pragma once
// The interface of kangcho's fast layouts (kangcho/gather.h: per-particle gather, any mesh;
// kangcho/stencil.h: grids): dv(0) and `iterations` Jacobi sweeps of the paper's system, computed
// in the layout's own data structures, in precision T, from the same kernels (kernels.h).

#include <cstdint>

#include "cloth/solver.h"
#include "cloth/thread_pool.h"

namespace cloth {

class KangChoLayout {
public:
    explicit KangChoLayout(ThreadPool& pool) : pool_(pool) {}
    virtual ~KangChoLayout() = default;
    // dv (3 x n, double; pinned particles get their prescribed change). forcesMs: the time spent
    // building the system.
    virtual void solve(const StepProblem& problem, int iterations, Points& dv, double* forcesMs) = 0;

protected:
    ThreadPool& pool_;  // the solver's
    std::uint64_t modelId_ = 0;  // the model the layout was prepared for
};

}  // namespace cloth
