#include "solvers/step_common.h"

#include "cloth/diagnostics.h"
#include "cloth/constraints.h"

#include <iterator>

namespace cloth {

const char* toString(StepStatus status) {
    static const char* const names[] = {"ok", "non-finite state", "solver failed"};
    const auto i = std::size_t(status);
    return i < std::size(names) ? names[i] : "?";
}

StepResult commit(const Model& model, ConstraintSet& constraints, const StepInput& input, ThreadPool& pool,
                  State& state, State& scratch, StepResult result) {
    const Index n = static_cast<Index>(state.x.cols());
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= n) continue;
        scratch.x.col(p.particle) = p.x;
        scratch.v.col(p.particle) = p.v;
    }
    // The corrections run on a finite state only (what they leave is finite too); the check after
    // them decides whether the step is kept.
    if (constraints.any() && scratch.x.allFinite()) constraints.apply(model, input.pins, input.h, scratch, &pool);
    const Index bad = firstNonFinite(scratch);
    if (bad >= 0) {
        result.status = StepStatus::NonFinite;
        result.badParticle = bad;
        return result;
    }
    std::swap(state.x, scratch.x);
    std::swap(state.v, scratch.v);
    return result;
}

StepResult ImplicitSolver::step(const Model& model, const Environment& env, State& state, const StepInput& input) {
    if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
    StepResult result;
    if (input.damping && Index(input.damping->size()) != model.particleCount()) return {StepStatus::SolverFailed, -1};
    if (!computeDv({model, env, state, input, config_.compressionRule}, result)) result.status = StepStatus::SolverFailed;
    if (result.status != StepStatus::Ok) return result;

    const auto t0 = Clock::now();
    scratch_.v = state.v + dv_;
    scratch_.x = state.x + input.h * scratch_.v;
    result = commit(model, constraints_, input, *pool_, state, scratch_, result);
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
