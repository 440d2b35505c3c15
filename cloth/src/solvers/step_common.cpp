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

Vec3 predictVelocity(const Model& model, const Environment& env, const StepInput& input, Index i, const Vec3& v, Scalar h) {
    const Scalar m = model.masses()[i];
    Vec3 b = m * v + h * m * env.gravity;
    Mat3 A = Mat3::Identity() * (m * (1 + h * env.drag));
    if (input.externalForce) b += h * input.externalForce->col(i);
    if (input.damping) {
        const Mat3& C = (*input.damping)[std::size_t(i)];
        A += h * C;
        b += h * (C * v);
    }
    return A.ldlt().solve(b);
}

}  // namespace cloth
