// multigrid: V-cycles on the system of the paper's step (multigrid.h): the paper's Jacobi sweep,
// damped, as the smoother, Galerkin coarse operators, a direct solve on the coarsest level. By
// default the V-cycle preconditions CG, until the relative residual is under the tolerance, with
// a cap; or a fixed number of cycles. The count used is in the step's result.

#include "multigrid.h"
#include "solver_table.h"
#include "solvers/step_common.h"

namespace cloth {

namespace {

class MultigridSolver final : public ImplicitSolver {
public:
    explicit MultigridSolver(SolverConfig config) : ImplicitSolver(std::move(config)) {
        const MultigridSettings& s = config_.get<MultigridSettings>();
        if (s.singlePrecision) float_ = std::make_unique<Multigrid<float>>(s, s.threads);
        else double_ = std::make_unique<Multigrid<double>>(s, s.threads);
    }
    std::string details() const override {
        return "levels: " + (float_ ? float_->describeHierarchy() : double_->describeHierarchy());
    }

protected:
    bool computeDv(const Model& model, const Environment& env, const State& state, const StepInput& input,
                   StepResult& result) override {
        MultigridStats stats;
        const auto t0 = Clock::now();
        const bool ok = float_ ? float_->solve(model, env, state, input, config_.compressionRule, dv_, stats, &profile_.forcesMs)
                               : double_->solve(model, env, state, input, config_.compressionRule, dv_, stats, &profile_.forcesMs);
        profile_.solveMs = msSince(t0) - profile_.forcesMs;
        result.iterations = stats.cycles;
        result.residual = stats.residual;
        return ok;
    }

private:
    std::unique_ptr<Multigrid<float>> float_;
    std::unique_ptr<Multigrid<double>> double_;
};

std::string check(const SolverConfig& c) {
    const MultigridSettings& s = c.get<MultigridSettings>();
    if (s.preSweeps + s.postSweeps == 0) return "solver 'multigrid': pre_sweeps + post_sweeps must be at least 1";
    if (s.singlePrecision && s.tolerance < 1e-6)
        return "solver 'multigrid' parameter tolerance = " + std::to_string(s.tolerance) +
               " is below what precision=float can reach (>= 1e-6)";
    return {};
}

}  // namespace

SolverKind multigridKind() {
    using S = MultigridSettings;
    using namespace keys;
    return {"multigrid",
            "V-cycles on the same system (damped Jacobi smoother, Galerkin coarse levels), as CG's preconditioner",
            [](SolverConfig& c) { c.settings = S{}; },
            with({shown(integer<S>("cycles", &S::cycles, 0, 1000, "fixed V-cycles; 0 = adaptive (tolerance, max_cycles)")),
                  real<S>("tolerance", &S::tolerance, 0, 1, true, true, "adaptive: relative residual to reach"),
                  integer<S>("max_cycles", &S::maxCycles, 1, 1000, "adaptive: at most this many cycles"),
                  integer<S>("pre_sweeps", &S::preSweeps, 0, 100, "smoothing sweeps before the coarse correction"),
                  integer<S>("post_sweeps", &S::postSweeps, 0, 100, "smoothing sweeps after it"),
                  real<S>("damping", &S::damping, 0, 1.5, true, false, "smoother: x += damping W_ii^-1 r"),
                  choice<S, S::Coarsening>("coarsening", &S::coarsening,
                                           {{"auto", S::Coarsening::Auto},
                                            {"geometric", S::Coarsening::Geometric},
                                            {"aggregation", S::Coarsening::Aggregation}},
                                           "auto: geometric on grids, smoothed aggregation on meshes"),
                  choice<S, S::CoarseOperator>("coarse", &S::coarseOperator,
                                               {{"galerkin", S::CoarseOperator::Galerkin},
                                                {"rediscretize", S::CoarseOperator::Rediscretized}},
                                               "coarse operators: P^T W P, or the cloth re-discretized (grids)"),
                  choice<S, bool>("krylov", &S::conjugateGradients, {{"cg", true}, {"none", false}},
                                  "cg: V-cycles precondition CG; none: V-cycles alone"),
                  integer<S>("threads", &S::threads, 1, 64, "worker threads (bit-identical results for any count)"),
                  choice<S, bool>("precision", &S::singlePrecision, {{"double", false}, {"float", true}},
                                  "arithmetic of the solve (the state stays double)")},
                 true),
            check, [](const SolverConfig& c) { return std::unique_ptr<Solver>(new MultigridSolver(c)); }};
}

}  // namespace cloth
