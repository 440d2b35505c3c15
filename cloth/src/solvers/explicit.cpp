#include "cloth/solvers/explicit_settings.h"
#include "cloth/solver_kind.h"
#include "solvers/step_common.h"

#include "cloth/diagnostics.h"

namespace cloth {

namespace {


// Symplectic Euler with substeps: v += hs f / m, x += hs v. Pinned particles move straight to
// their targets.
class ExplicitSolver final : public Solver {
public:
    StepResult step(const Model& model, const Environment& env, State& state,
                    const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        const Index n = model.particleCount();
        const int substeps = settings<ExplicitSettings>().substeps;
        const Scalar hs = input.h / substeps;
        const auto& mass = model.masses();
        std::vector<std::uint8_t> pinned(n, 0);
        Points pinVelocity = Points::Zero(3, n);
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < n) {
                pinned[p.particle] = 1;
                pinVelocity.col(p.particle) = (p.x - state.x.col(p.particle)) / input.h;
            }
        profile_ = {};
        scratch_.x = state.x;
        scratch_.v = state.v;
        for (int k = 0; k < substeps; ++k) {
            auto t0 = Clock::now();
            computeForces(model, env, scratch_, input.externalForce, force_);
            profile_.forcesMs += msSince(t0);
            t0 = Clock::now();
            for (Index i = 0; i < n; ++i) {
                if (pinned[i]) scratch_.v.col(i) = pinVelocity.col(i);
                else scratch_.v.col(i) += hs / mass[i] * force_.col(i);
                scratch_.x.col(i) += hs * scratch_.v.col(i);
            }
            profile_.solveMs += msSince(t0);
        }
        auto t0 = Clock::now();
        dv_ = scratch_.v - state.v;
        StepResult result = commitStep(model, constraints_, input, *pool_, state, scratch_, StepResult{});
        result.iterations = substeps;
        profile_.integrateMs = msSince(t0);
        return result;
    }

private:
    State scratch_;
    Points force_;
};

}  // namespace

FLAGSIM_SOLVER_KIND(explicit) {
    using X = ExplicitSettings;
    using key = SolverKeys;
    return {"explicit", "symplectic Euler: v += h f / m, x += h v, in substeps", defaultsTo<X>,
            withCommon({key::shown(key::integer("substeps", &X::substeps, 1, 100000, "substeps per step"))}, false),
            {},
            createSolver<ExplicitSolver>};
}

}  // namespace cloth
