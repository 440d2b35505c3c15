#pragma once
// What every solver's step shares: timing, the commit of a finished step (step_commit.h), and the
// shape of an implicit step (build, solve for dv, v += dv, x += h v).

#include <chrono>

#include "cloth/solver.h"
#include "cloth/step_commit.h"

namespace cloth {

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Particle i's velocity after a step of h in gravity, the environment's drag c and the external
// force f_i (the air), the last two implicit in velocity through its damping block C_i
// (StepInput::damping): v* from (m (1 + h c) I + h C_i) v* = m v + h (m g + f_i + C_i v). The
// prediction of the position-based steps (xpbd, vbd): x_n + h v*.
Vec3 predictVelocity(const Model& model, const Environment& env, const StepInput& input, Index i, const Vec3& v, Scalar h);

// Backward Euler step shape shared by every implicit solver: the system, dv, then v += dv,
// x += h v. Subclasses supply dv.
class ImplicitSolver : public Solver {
public:
    StepResult step(const Model& model, const Environment& env, State& state, const StepInput& input) override;

protected:
    // Fills dv_ and profile_.forcesMs / solveMs. By default: the assembled system (sys_), then
    // solve().
    virtual bool computeDv(const StepProblem& problem, StepResult& result);
    virtual bool solve(const Model& model, StepResult& result);
    LinearSystem sys_;
    State scratch_;
};

}  // namespace cloth
