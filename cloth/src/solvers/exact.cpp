// exact and cg: the system every implicit solver reads, solved to a tolerance. Not reaching the
// tolerance is a failed step, never an approximation passed off as exact.
//   method=cholesky   sparse LDL^T with iterative refinement
//   method=cg         conjugate gradients (Eigen's, diagonal preconditioner), warm-started at dv(0)
//   method=multigrid  multigrid-preconditioned CG (multigrid.h): O(n) per cycle

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include "multigrid.h"
#include "solver_table.h"
#include "solvers/step_common.h"

namespace cloth {

bool solveExact(const Model& model, const LinearSystem& sys, Points& dv, Scalar* residual, Scalar tolerance) {
    const Eigen::SparseMatrix<Scalar> W = assembleMatrix(model, sys);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<Scalar>> chol(W);
    if (chol.info() != Eigen::Success) return false;
    const Eigen::Map<const Eigen::VectorXd> b(sys.rhs.data(), sys.rhs.size());
    Eigen::VectorXd x = chol.solve(b);
    // Iterative refinement: a few residual corrections bring the relative residual to rounding
    // level even for ill-conditioned (stiff, small h) systems.
    const Scalar bNorm = std::max(b.norm(), Scalar(1e-300));
    Scalar rel = (W * x - b).norm() / bNorm;
    for (int k = 0; k < 3 && rel > std::min(tolerance, Scalar(1e-12)); ++k) {
        x += chol.solve(b - W * x);
        rel = (W * x - b).norm() / bNorm;
    }
    if (residual) *residual = rel;
    dv = Eigen::Map<const Points>(x.data(), 3, model.particleCount());
    return x.allFinite() && rel <= tolerance;
}

namespace {

class ExactSolver final : public ImplicitSolver {
public:
    explicit ExactSolver(SolverConfig config) : ImplicitSolver(std::move(config)), s_(config_.get<ExactSettings>()) {}

protected:
    bool computeDv(const Model& model, const Environment& env, const State& state, const StepInput& input,
                   StepResult& result) override {
        if (s_.method != ExactSettings::Method::Multigrid)
            return ImplicitSolver::computeDv(model, env, state, input, result);
        if (!multigrid_) {
            MultigridSettings m;
            m.tolerance = s_.tolerance;
            m.maxCycles = std::min(s_.maxIterations, 1000);
            multigrid_ = std::make_unique<Multigrid<double>>(m, 1);
        }
        MultigridStats stats;
        const auto t0 = Clock::now();
        const bool ok = multigrid_->solve(model, env, state, input, config_.compressionRule, dv_, stats, &profile_.forcesMs);
        profile_.solveMs = msSince(t0) - profile_.forcesMs;
        result.iterations = stats.cycles;
        result.residual = stats.residual;
        return ok && stats.residual <= s_.tolerance;
    }
    bool solve(const Model& model, StepResult& result) override {
        if (s_.method == ExactSettings::Method::Cholesky) {
            result.iterations = 1;
            return solveExact(model, sys_, dv_, &result.residual, s_.tolerance);
        }
        const Eigen::SparseMatrix<Scalar> W = assembleMatrix(model, sys_);
        Eigen::ConjugateGradient<Eigen::SparseMatrix<Scalar>, Eigen::Lower | Eigen::Upper> cg;
        cg.setTolerance(s_.tolerance);
        cg.setMaxIterations(s_.maxIterations);
        cg.compute(W);
        const Eigen::Map<const Eigen::VectorXd> b(sys_.rhs.data(), sys_.rhs.size());
        // Warm start from the Jacobi guess dv(0): cheap and always at least as good as zero.
        jacobiStart(sys_, dv_);
        const Eigen::VectorXd x0 = Eigen::Map<const Eigen::VectorXd>(dv_.data(), dv_.size());
        const Eigen::VectorXd x = cg.solveWithGuess(b, x0);
        result.iterations = static_cast<int>(cg.iterations());
        result.residual = cg.error();
        dv_ = Eigen::Map<const Points>(x.data(), 3, model.particleCount());
        return x.allFinite() && cg.info() == Eigen::Success && cg.error() <= s_.tolerance;
    }

private:
    ExactSettings s_;
    std::unique_ptr<Multigrid<double>> multigrid_;
};

std::vector<SolverKey> exactKeys(bool withMethod) {
    using S = ExactSettings;
    using namespace keys;
    std::vector<SolverKey> own;
    if (withMethod)
        own.push_back(shown(choice<S, S::Method>(
            "method", &S::method,
            {{"cholesky", S::Method::Cholesky}, {"cg", S::Method::CG}, {"multigrid", S::Method::Multigrid}},
            "how the system is solved")));
    own.push_back(shown(real<S>("tolerance", &S::tolerance, 0, 1, true, true,
                                "relative residual the solve must reach, else the step fails")));
    own.push_back(integer<S>("max_iterations", &S::maxIterations, 1, 1000000,
                             "cg: iterations; multigrid: V-cycles (at most 1000)"));
    return with(std::move(own), true);
}

std::unique_ptr<Solver> makeExact(const SolverConfig& c) { return std::unique_ptr<Solver>(new ExactSolver(c)); }

}  // namespace

SolverKind exactKind() {
    return {"exact", "the same system solved to a tolerance: the reference",
            [](SolverConfig& c) { c.settings = ExactSettings{}; }, exactKeys(true), {}, makeExact};
}

SolverKind cgKind() {
    return {"cg", "exact with method=cg: conjugate gradients, diagonal preconditioner",
            [](SolverConfig& c) {
                ExactSettings s;
                s.method = ExactSettings::Method::CG;
                c.settings = s;
            },
            exactKeys(false), {}, makeExact};
}

}  // namespace cloth
