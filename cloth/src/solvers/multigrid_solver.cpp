// multigrid: cycles on the system of the paper's step (multigrid.h): the paper's Jacobi sweep,
// damped, as the smoother, Galerkin coarse operators, a direct solve on the coarsest level. By
// default the cycle (a K-cycle on level 1) preconditions CG, until the relative residual is under
// the tolerance, with a cap; or a fixed number of V-cycles. The count is in the step's result.

#include <algorithm>
#include <variant>

#include "multigrid/multigrid.h"
#include "solver_table.h"
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
    bool strict() const { return std::holds_alternative<ExactSettings>(config_.settings); }
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

std::unique_ptr<Solver> makeMultigridSolver(const SolverConfig& config) { return createSolver<MultigridSolver>(config); }

}  // namespace cloth
