// xpbd: the springs as compliant distance constraints (Macklin, Mueller & Chentanez 2016), in
// small steps (Macklin et al. 2019). Spring s, C_s = |x_j - x_i| - l0, with compliance 1/k_s, has
// the spring's energy k_s C_s^2 / 2, so the step's fixed point is backward Euler in the springs:
//   M (x - xTilde) = h^2 f_springs(x),   xTilde = x_n + h v*,
// with v* the velocity after gravity, the environment's drag and the external force (the air),
// the last two implicit in velocity (StepInput::damping) so that light particles in a gale stay
// stable. Each Gauss-Seidel pass moves both ends of every spring along it by
//   dLambda = -(C + alphaTilde lambda) / (w_i + w_j + alphaTilde),  alphaTilde = 1 / (k h^2),
// x_i -= w_i n dLambda, x_j += w_j n dLambda (w = 1/m; pinned: 0). With chains=on a grid's rows
// and columns of structural springs are each projected at once first (xpbd_chains.h). Then
// v = (x - x_n) / h. The passes run in a fixed order on one thread: the same bits for any caller.

#include "cloth/solvers/xpbd_settings.h"
#include "cloth/solver_kind.h"
#include "solvers/step_common.h"
#include "solvers/xpbd_chains.h"

#include "cloth/diagnostics.h"
#include "cloth/forces.h"

namespace cloth {

namespace {


class XpbdSolver final : public Solver {
public:
    StepResult step(const Model& model, const Environment& env, State& state, const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        profile_ = {};
        auto t0 = Clock::now();
        setWeights(model, input);
        predict(model, env, state, input);
        profile_.forcesMs = msSince(t0);
        t0 = Clock::now();
        const int passes = settings<XpbdSettings>().iterations;
        lambda_.assign(model.springs().size(), 0);
        const bool chains = settings<XpbdSettings>().chains;
        for (int pass = 0; pass < passes; ++pass) {
            if (chains) chains_.project(model, weight_, input.h, lambda_, scratch_.x.data());
            project(model, input.h, chains);
        }
        for (Index i = 0; i < model.particleCount(); ++i)
            if (weight_[i] > 0) scratch_.v.col(i) = (scratch_.x.col(i) - state.x.col(i)) / input.h;
        profile_.solveMs = msSince(t0);
        t0 = Clock::now();
        dv_ = scratch_.v - state.v;
        StepResult result;
        result.iterations = passes;
        result = commitStep(model, constraints_, input, *pool_, state, scratch_, result);
        profile_.integrateMs = msSince(t0);
        return result;
    }

private:
    // w_i = 1 / m_i; pinned particles 0 (the projection does not move them).
    void setWeights(const Model& model, const StepInput& input) {
        const Index n = model.particleCount();
        weight_.resize(std::size_t(n));
        for (Index i = 0; i < n; ++i) weight_[i] = 1 / model.masses()[i];
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < n) weight_[p.particle] = 0;
    }

    // v* from (m (1 + h c) I + h C_i) v* = m v + h (m g + f_i + C_i v) (f: the external force, C_i:
    // its damping block, c: the environment's drag), then x = x_n + h v*. Pinned particles go to
    // their targets.
    void predict(const Model& model, const Environment& env, const State& state, const StepInput& input) {
        const Scalar h = input.h;
        scratch_.x = state.x;
        scratch_.v = state.v;
        for (Index i = 0; i < model.particleCount(); ++i) {
            if (weight_[i] == 0) continue;
            scratch_.v.col(i) = predictVelocity(model, env, input, i, state.v.col(i), h);
            scratch_.x.col(i) = state.x.col(i) + h * scratch_.v.col(i);
        }
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < model.particleCount()) {
                scratch_.x.col(p.particle) = p.x;
                scratch_.v.col(p.particle) = p.v;
            }
    }

    // One Gauss-Seidel pass over the springs (but the chains' when `chains`), lambda_ accumulating
    // each spring's multiplier.
    void project(const Model& model, Scalar h, bool chains) {
        const std::vector<Spring>& springs = model.springs();
        Scalar* x = scratch_.x.data();
        for (std::size_t s = 0; s < springs.size(); ++s) {
            const Spring& sp = springs[s];
            const Scalar wi = weight_[sp.i], wj = weight_[sp.j];
            if (wi + wj == 0 || !(sp.k > 0) || (chains && chains_.isChained(s))) continue;
            Scalar* xi = x + 3 * sp.i;
            Scalar* xj = x + 3 * sp.j;
            const Scalar d0 = xj[0] - xi[0], d1 = xj[1] - xi[1], d2 = xj[2] - xi[2];
            const Scalar L = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
            if (L < kMinSpringLength) continue;
            const Scalar alpha = 1 / (sp.k * h * h);
            const Scalar dLambda = -(L - sp.rest + alpha * lambda_[s]) / (wi + wj + alpha);
            lambda_[s] += dLambda;
            const Scalar ai = wi * dLambda / L, aj = wj * dLambda / L;
            xi[0] -= ai * d0, xi[1] -= ai * d1, xi[2] -= ai * d2;
            xj[0] += aj * d0, xj[1] += aj * d1, xj[2] += aj * d2;
        }
    }

    std::vector<Scalar> weight_, lambda_;
    State scratch_;
    XpbdChains chains_;
};

}  // namespace

FLAGSIM_SOLVER_KIND(xpbd) {
    using P = XpbdSettings;
    using key = SolverKeys;
    return {"xpbd", "the springs as compliant constraints (compliance 1/k), Gauss-Seidel projection; in small steps",
            defaultsTo<P>,
            withCommon({key::shown(key::integer("iterations", &P::iterations, 1, 10000, "passes over the springs per step")),
                        key::shown(key::choice("chains", &P::chains, {{"on", true}, {"off", false}},
                                               "on: a grid's rows and columns of structural springs each a chain solved at "
                                               "once (tridiagonal), the rest Gauss-Seidel; off: all Gauss-Seidel"))},
                       false),
            {},
            createSolver<XpbdSolver>};
}

}  // namespace cloth
