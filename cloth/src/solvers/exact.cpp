// exact and cg: the system every implicit solver reads, solved to a tolerance. Not reaching the
// tolerance is a failed step, never an approximation passed off as exact.
//   method=cholesky   sparse LDL^T with iterative refinement
//   method=cg         conjugate gradients (Eigen's, diagonal preconditioner), warm-started at dv(0)
//   method=multigrid  multigrid-preconditioned CG (multigrid.h): O(n) per cycle

#include <Eigen/IterativeLinearSolvers>

#include "cloth/paper_step.h"
#include "cloth/solver_kind.h"
#include "cloth/exact_solve.h"
#include "cloth/solvers/exact_settings.h"
#include "solvers/step_common.h"

namespace cloth {

namespace {

// method=cholesky or cg; method=multigrid is the multigrid solver held to the tolerance.
class ExactSolver final : public ImplicitSolver {
    bool solve(const Model& model, StepResult& result) override {
        const ExactSettings& s = settings<ExactSettings>();
        if (s.method == ExactSettings::Method::Cholesky) {
            result.iterations = 1;
            return solveExact(model, sys_, dv_, &result.residual, s.tolerance);
        }
        const Eigen::SparseMatrix<Scalar> W = assembleMatrix(model, sys_);
        Eigen::ConjugateGradient<Eigen::SparseMatrix<Scalar>, Eigen::Lower | Eigen::Upper> cg;
        const bool fixed = s.iterations > 0;  // an approximation: run exactly that many
        cg.setTolerance(fixed ? Scalar(0) : s.tolerance);
        cg.setMaxIterations(fixed ? s.iterations : s.maxIterations);
        cg.compute(W);
        const Eigen::Map<const Eigen::VectorXd> b(sys_.rhs.data(), sys_.rhs.size());
        // Warm start from the Jacobi guess dv(0): cheap and always at least as good as zero.
        jacobiStart(sys_, dv_);
        const Eigen::VectorXd x0 = Eigen::Map<const Eigen::VectorXd>(dv_.data(), dv_.size());
        const Eigen::VectorXd x = cg.solveWithGuess(b, x0);
        result.iterations = static_cast<int>(cg.iterations());
        result.residual = cg.error();
        dv_ = Eigen::Map<const Points>(x.data(), 3, model.particleCount());
        return x.allFinite() && (fixed || (cg.info() == Eigen::Success && cg.error() <= s.tolerance));
    }
};

}  // namespace

// exact:method=multigrid is the multigrid solver held to the tolerance (multigrid_solver.cpp).
std::unique_ptr<Solver> makeStrictMultigridSolver(const SolverConfig& config);

namespace {

std::unique_ptr<Solver> makeExactSolver(const SolverConfig& config) {
    if (config.get<ExactSettings>().method == ExactSettings::Method::Multigrid) return makeStrictMultigridSolver(config);
    return createSolver<ExactSolver>(config);
}

// The keys of exact (with method=) and of cg (with iterations= instead).
std::vector<SolverKey> exactKeys(bool withMethod) {
    using E = ExactSettings;
    using key = SolverKeys;
    std::vector<SolverKey> own;
    if (withMethod)
        own.push_back(key::shown(key::choice(
            "method", &E::method,
            {{"cholesky", E::Method::Cholesky}, {"cg", E::Method::CG}, {"multigrid", E::Method::Multigrid}},
            "how the system is solved")));
    else
        own.push_back(key::integer("iterations", &E::iterations, 0, 1000000,
                                   "a fixed number of iterations, an approximation; 0 = until the tolerance"));
    own.push_back(key::shown(key::real("tolerance", &E::tolerance, 0, 1, true, true,
                                       "relative residual the solve must reach, else the step fails")));
    own.push_back(key::integer("max_iterations", &E::maxIterations, 1, 1000000,
                               "cg: iterations; multigrid: cycles (at most 1000)"));
    return withCommon(std::move(own), true);
}

void cgDefaults(SolverConfig& c) {
    ExactSettings s;
    s.method = ExactSettings::Method::CG;
    c.settings = s;
}

}  // namespace

FLAGSIM_SOLVER_KIND(exact) {
    return {"exact", "the same system solved to a tolerance: the reference", defaultsTo<ExactSettings>,
            exactKeys(true), {}, makeExactSolver};
}

FLAGSIM_SOLVER_KIND(cg) {
    return {"cg", "exact with method=cg: conjugate gradients, diagonal preconditioner", cgDefaults, exactKeys(false), {},
            makeExactSolver};
}

}  // namespace cloth
