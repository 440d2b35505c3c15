// newton: the implicit step solved to convergence (nonlinear/newton.h), by one of three
// integrators, each the step's equations (step_equations.h) for some xHat, vHat, k:
//   backward Euler   x_n, v_n, h
//   BDF2             (4 x_n - x_{n-1}) / 3, (4 v_n - v_{n-1}) / 3, 2 h / 3 (Choi & Ko 2002). It keeps
//                    the state its last step started from; its first step, and any step after
//                    resetHistory(), a change of h or of the model, is a backward Euler step.
//   theta-midpoint   x_n, v_n, theta h for the stage velocity u (forces at x_n + theta h u, u);
//                    then v_{n+1} = v_n + (u - v_n) / theta, x_{n+1} = x_n + h u. theta = 1/2 is
//                    the implicit midpoint rule (second order, no numerical damping).
// With StepInput::air the solver evaluates the air itself at every iterate (couplesAir(), air=coupled);
// with air=frozen it takes the caller's air force at the step's start and its drag as
// StepInput::damping, linear in v about v_n.

#include "nonlinear/newton.h"
#include "cloth/solvers/newton_settings.h"
#include "cloth/solver_kind.h"
#include "solvers/step_common.h"

#include "cloth/diagnostics.h"

namespace cloth {

namespace {

// The kind's settings; each field's key, with its doc, is in the kind's table at the end.

class NewtonSolver final : public Solver {
public:
    bool couplesAir() const override { return settings<NewtonSettings>().coupledAir; }
    void resetHistory() override { previous_ = {}; }

    StepResult step(const Model& model, const Environment& env, State& state, const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        if (!newton_) newton_ = std::make_unique<NewtonSolve>(pool_);
        const NewtonSettings& s = settings<NewtonSettings>();
        auto t0 = Clock::now();
        StepEquations eq{model, env, input, state.x, state.v, input.h, config_.compressionRule, {}, &state.v};
        const bool bdf2 = s.integrator == NewtonSettings::Integrator::BDF2 && previous_.x.cols() == state.x.cols() &&
                          previousH_ == input.h && previousModel_ == model.id();
        if (bdf2) {
            eq.xHat = (4 * state.x - previous_.x) / 3;
            eq.vHat = (4 * state.v - previous_.v) / 3;
            eq.k = 2 * input.h / 3;
        }
        const bool midpoint = s.integrator == NewtonSettings::Integrator::Midpoint;
        const Scalar theta = midpoint ? s.theta : 1;
        eq.k *= theta;
        State iterate = state;
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < model.particleCount()) {
                iterate.v.col(p.particle) = state.v.col(p.particle) + theta * (p.v - state.v.col(p.particle));
                eq.pinX.emplace_back(p.particle, state.x.col(p.particle) + theta * (p.x - state.x.col(p.particle)));
            }
        NewtonStats stats;
        const bool ok = newton_->solve(eq, {s.maxIterations, s.tolerance, s.linearTolerance}, iterate, stats);
        if (midpoint) {  // from the stage velocity u to the end of the step
            iterate.x = state.x + (iterate.x - state.x) / theta;
            iterate.v = state.v + (iterate.v - state.v) / theta;
        }
        profile_ = {};
        profile_.solveMs = msSince(t0);
        StepResult result;
        result.iterations = stats.iterations;
        result.linearIterations = stats.linearIterations;
        result.residual = stats.residual;
        if (!ok) return {StepStatus::SolverFailed, -1, stats.iterations, stats.residual, stats.linearIterations};
        t0 = Clock::now();
        dv_ = iterate.v - state.v;
        State start = state;
        result = commitStep(model, constraints_, input, *pool_, state, iterate, result);
        if (result.status == StepStatus::Ok) {
            previous_ = std::move(start);
            previousH_ = input.h;
            previousModel_ = model.id();
        }
        profile_.integrateMs = msSince(t0);
        return result;
    }

private:
    std::unique_ptr<NewtonSolve> newton_;
    State previous_;  // the state the last step started from (BDF2's x_{n-1}, v_{n-1})
    Scalar previousH_ = 0;
    std::uint64_t previousModel_ = 0;
};

}  // namespace

FLAGSIM_SOLVER_KIND(newton) {
    using N = NewtonSettings;
    using key = SolverKeys;
    return {"newton", "the implicit step converged: Newton iterations, GMRES with multigrid, the air fully coupled",
            defaultsTo<N>,
            withCommon(
                {key::shown(key::choice("integrator", &N::integrator,
                                        {{"be", N::Integrator::BackwardEuler}, {"bdf2", N::Integrator::BDF2},
                                         {"midpoint", N::Integrator::Midpoint}},
                                        "backward Euler; BDF2 (Choi & Ko 2002; its first step backward Euler); theta-midpoint")),
                 key::real("theta", &N::theta, 0.5, 1, false, false,
                           "midpoint: forces at x_n + theta h u; 1/2 damps no mode, 1 is backward Euler"),
                 key::integer("max_iterations", &N::maxIterations, 1, 100, "Newton iterations per step; 1 = the linearized step"),
                 key::real("tolerance", &N::tolerance, 0, 1e3, true, false,
                           "stop when the last iteration changed no velocity by more (m/s)"),
                 key::real("linear_tolerance", &N::linearTolerance, 0, 1, true, true, "relative residual of each linear solve"),
                 key::choice("air", &N::coupledAir, {{"coupled", true}, {"frozen", false}},
                             "coupled: the air at every iterate, its whole derivative; frozen: the air at the step's start, "
                             "its drag implicit in velocity"),
                 threadsKey<N>()},
                true),
            {},
            createSolver<NewtonSolver>};
}

}  // namespace cloth
