#include "solvers/step_common.h"

#include "cloth/diagnostics.h"
#include "cloth/paper_step.h"

namespace cloth {

StepResult ImplicitSolver::step(const Model& model, const Environment& env, State& state, const StepInput& input) {
    if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
    StepResult result;
    if (input.damping && Index(input.damping->size()) != model.particleCount()) return {StepStatus::SolverFailed, -1};
    if (!computeDv({model, env, state, input, config_.compressionRule}, result)) result.status = StepStatus::SolverFailed;
    if (result.status != StepStatus::Ok) return result;

    const auto t0 = Clock::now();
    scratch_.v = state.v + dv_;
    scratch_.x = state.x + input.h * scratch_.v;
    result = commitStep(model, constraints_, input, *pool_, state, scratch_, result);
    profile_.integrateMs = msSince(t0);
    return result;
}

bool ImplicitSolver::computeDv(const StepProblem& problem, StepResult& result) {
    auto t0 = Clock::now();
    buildSystem(problem, sys_);
    profile_.forcesMs = msSince(t0);
    t0 = Clock::now();
    const bool ok = solve(problem.model, result);
    profile_.solveMs = msSince(t0);
    return ok;
}

bool ImplicitSolver::solve(const Model&, StepResult&) { return false; }

}  // namespace cloth
