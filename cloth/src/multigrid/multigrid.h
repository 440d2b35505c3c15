#pragma once
// Multigrid for the linearized backward Euler system that every implicit solver here reads: a
// small facade over the components in this folder.
//   fine_system      level 0's W and b from the state (banded springs on grids, gathered on meshes)
//   hierarchy        transfers (transfer.h), Galerkin coarse operators (galerkin.h, by stencil on
//                    nested grids: nested_galerkin.h; bend springs collapsed: bend_collapse.h),
//                    the coarsest factorization
//   cycle            damped block-Jacobi relaxation, the V- or K-cycle
//   krylov           conjugate gradients on a system given as functions
//   stopping         the adaptive stop (relative and local)
//   warm_start       the start from the last solves
//   reductions       sums with the same bits for any thread count
// Mixed precision is a float hierarchy (its level 0 the double W rounded) whose cycles precondition
// the double CG. Every loop runs over rows split across threads, and every sum over rows runs in
// fixed chunks in a fixed order: the result is bit-identical for any thread count.

#include <Eigen/Dense>
#include <memory>
#include <string>

#include "block_matrix.h"
#include "cloth/solvers/multigrid_settings.h"
#include "cloth/solver.h"
#include "cloth/thread_pool.h"

namespace cloth {

struct MultigridStats {
    int cycles = 0;  // cycles applied (with conjugate gradients: CG iterations, one cycle each)
    double residual = -1;  // relative residual |b - W dv| / |b| over free particles (-1: not computed)
};

template <class T>
class Multigrid {
public:
    // Worker threads: `pool`, or (null) a pool of settings.threads of its own.
    explicit Multigrid(const MultigridSettings& settings, std::shared_ptr<ThreadPool> pool = nullptr);
    ~Multigrid();

    // Builds the problem's system and solves it; dv gets the pinned particles' prescribed change.
    // Returns false when the result is not finite. forcesMs: time of the system build.
    bool solve(const StepProblem& problem, Points& dv, MultigridStats& stats, double* forcesMs = nullptr);

    // The hierarchy's pieces, for tests and diagnostics (valid after solve or prepareSystem).
    void prepareSystem(const StepProblem& problem);
    int levels() const;
    const BlockMatrix<T>& matrix(int level) const;
    Eigen::MatrixXd prolongation(int level) const;  // dense P from level + 1 to level
    // One cycle from x = 0 for the right-hand side b (3n, particle-major); returns x.
    Eigen::VectorXd vcycle(const Eigen::VectorXd& b);
    // What coarse level `level` hands back to the finer one for its right-hand side b (3 n_level,
    // in the level's point order): one cycle from there, or on a K-cycle level two flexible CG
    // iterations each preconditioned by one. Level 0: vcycle(b).
    Eigen::VectorXd coarseSolve(int level, const Eigen::VectorXd& b);
    std::string describeHierarchy() const;

    // As the preconditioner of another solver's system (the Newton step's, nonlinear/): after
    // prepareSystem(problem), rebuildCoarse() builds the coarse levels for it; then product() is
    // level 0's W x and precondition() one cycle from zero, on 3n particle-major vectors whose
    // pinned rows stay zero. Level 0 may be rebuilt by prepareSystem while the coarse levels stay.
    void rebuildCoarse();
    void product(const std::vector<double>& x, std::vector<double>& y);
    void precondition(const std::vector<double>& r, std::vector<double>& z);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

extern template class Multigrid<float>;
extern template class Multigrid<double>;

}  // namespace cloth
