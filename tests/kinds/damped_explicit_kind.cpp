// A solver kind that the library does not ship, in one file, as a new kind is written: its
// settings struct, its key table and its factory. The tests register it (registerSolverKind, as a
// program adding its own kind would) and find it in --help, the README's table, the parser and
// the demo's panel, which all read the registry.
//
// damped_explicit: symplectic Euler with a velocity damping factor per step,
//   v <- (v + h f / m) (1 - damping),  x <- x + h v.

#include "tests/kinds/damped_explicit_kind.h"

#include "cloth/diagnostics.h"
#include "cloth/forces.h"
#include "cloth/step_commit.h"

namespace cloth {

namespace {

struct DampedExplicitSettings {
    double damping = 0.01;
    int threads = 1;
};

class DampedExplicitSolver final : public Solver {
public:
    StepResult step(const Model& model, const Environment& env, State& state, const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        const double keep = 1 - settings<DampedExplicitSettings>().damping;
        computeForces(model, env, state, input.externalForce, force_);
        scratch_.v = state.v;
        for (Index i = 0; i < model.particleCount(); ++i)
            scratch_.v.col(i) = (scratch_.v.col(i) + input.h / model.masses()[i] * force_.col(i)) * keep;
        scratch_.x = state.x + input.h * scratch_.v;
        dv_ = scratch_.v - state.v;
        return commitStep(model, constraints_, input, *pool_, state, scratch_, StepResult{});
    }

private:
    State scratch_;
    Points force_;
};

}  // namespace

SolverKind dampedExplicitKind() {
    using D = DampedExplicitSettings;
    using key = SolverKeys;
    return {kDampedExplicit, "symplectic Euler with a velocity damping factor per step (a test's own kind)",
            defaultsTo<D>,
            withCommon({key::shown(key::real("damping", &D::damping, 0, 1, false, true, "velocity lost per step")),
                        threadsKey<D>()},
                       false),
            {},
            createSolver<DampedExplicitSolver>};
}

}  // namespace cloth
