// multigrid: cycles on the system of the paper's step (multigrid.h): the paper's Jacobi sweep,
// damped, as the smoother, Galerkin coarse operators, a direct solve on the coarsest level. By
// default the cycle (a K-cycle on level 1) preconditions CG, until the relative residual is under
// the tolerance, with a cap; or a fixed number of V-cycles. The count is in the step's result.

#include <algorithm>
#include <typeinfo>

#include "multigrid/multigrid.h"
#include "cloth/solver_kind.h"
#include "cloth/solvers/exact_settings.h"
#include "solvers/step_common.h"

namespace cloth {

namespace {

class MultigridSolver final : public ImplicitSolver {
public:
    std::string details() const override {
        return "levels: " + (float_ ? float_->describeHierarchy() : double_ ? double_->describeHierarchy() : "(not built)");
    }

private:
    // exact:method=multigrid runs here too: CG with cycles to its tolerance, which it must reach.
    bool strict() const { return config_.settings.type() == typeid(ExactSettings); }
    MultigridSettings multigridSettings() const {
        if (!strict()) return settings<MultigridSettings>();
        MultigridSettings m;
        m.tolerance = settings<ExactSettings>().tolerance;
        m.maxCycles = std::min(settings<ExactSettings>().maxIterations, 1000);
        MultigridTuning tuning = settledTuning(m);
        tuning.localTolerance = 0;  // the reference stops on its relative residual alone
        m.tuning = tuning;
        return m;
    }
    bool computeDv(const StepProblem& problem, StepResult& result) override {
        if (!float_ && !double_) {
            const MultigridSettings s = multigridSettings();
            if (s.precision == MultigridSettings::Precision::Float) float_ = std::make_unique<Multigrid<float>>(s, pool_);
            else double_ = std::make_unique<Multigrid<double>>(s, pool_);
        }
        MultigridStats stats;
        const auto t0 = Clock::now();
        const bool ok = float_ ? float_->solve(problem, dv_, stats, &profile_.forcesMs)
                               : double_->solve(problem, dv_, stats, &profile_.forcesMs);
        profile_.solveMs = msSince(t0) - profile_.forcesMs;
        result.iterations = stats.cycles;
        result.residual = stats.residual;
        return ok && (!strict() || stats.residual <= settings<ExactSettings>().tolerance);
    }

    std::unique_ptr<Multigrid<float>> float_;
    std::unique_ptr<Multigrid<double>> double_;
};

}  // namespace

std::unique_ptr<Solver> makeStrictMultigridSolver(const SolverConfig& config) { return createSolver<MultigridSolver>(config); }

namespace {

// multigrid's own keys: what a user chooses. Its tuning (MultigridTuning) is not a key.
std::vector<SolverKey> multigridKeys() {
    using M = MultigridSettings;
    using P = M::Precision;
    using key = SolverKeys;
    return withCommon({key::shown(key::integer("cycles", &M::cycles, 0, 1000, "fixed cycles; 0 = adaptive (tolerance, max_cycles)")),
                       key::real("tolerance", &M::tolerance, 0, 1, true, true, "adaptive: relative residual to reach"),
                       key::integer("max_cycles", &M::maxCycles, 1, 1000, "adaptive: at most this many cycles"),
                       threadsKey<M>(),
                       key::choice("precision", &M::precision,
                                   {{"double", P::Double}, {"mixed", P::Mixed}, {"float", P::Float}},
                                   "arithmetic of the solve (the state stays double); mixed: float cycles "
                                   "preconditioning a double CG")},
                      true);
}

std::string multigridCheck(const SolverConfig& c) {
    const MultigridSettings& s = c.get<MultigridSettings>();
    if (s.precision == MultigridSettings::Precision::Float && s.tolerance < 1e-6)
        return "solver 'multigrid' parameter tolerance = " + std::to_string(s.tolerance) +
               " is below what precision=float can reach (>= 1e-6)";
    if (!s.tuning) return {};
    if (s.tuning->preSweeps + s.tuning->postSweeps == 0)
        return "solver 'multigrid': its tuning has no smoothing sweeps (pre + post must be at least 1)";
    if (s.precision == MultigridSettings::Precision::Mixed && !s.tuning->krylov)
        return "solver 'multigrid' parameter precision = mixed needs its tuning's CG (the double CG corrects the "
               "float cycles)";
    return {};
}

}  // namespace

FLAGSIM_SOLVER_KIND(multigrid) {
    return {"multigrid",
            "multigrid cycles on the same system (damped Jacobi smoother, Galerkin coarse levels), as CG's preconditioner",
            defaultsTo<MultigridSettings>, multigridKeys(), multigridCheck, createSolver<MultigridSolver>};
}

}  // namespace cloth
