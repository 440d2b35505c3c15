#include <Eigen/SparseCholesky>

#include "kernels.h"
#include "cloth/solvers/desbrun_settings.h"
#include "cloth/solver_kind.h"
#include "solvers/step_common.h"

#include "cloth/diagnostics.h"

namespace cloth {

namespace {

// Desbrun, Schroder & Barr 1999 ("Interactive animation of structured deformable objects"), the
// paper's ref. [5]: the Jacobian is replaced by its constant, isotropic linear part, J_ij ~ k I
// (a Laplacian of spring stiffnesses), so the implicit matrix A = M + h^2 k L (x) I3 never changes
// and is factored once ("precomputed filter"); each step solves
//   A dv = h f(x) - h^2 k L v        (f with the full nonlinear springs)
// three times (x, y, z) with that factorization. Pinned particles are eliminated as everywhere
// here. Desbrun et al.'s post-step correction of the angular momentum the filter disturbs is not
// applied (documented in docs/study.md).
class DesbrunSolver final : public Solver {
public:
    StepResult step(const Model& model, const Environment& env, State& state, const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        const Index n = model.particleCount();
        const Scalar h = input.h, h2 = h * h;
        auto t0 = Clock::now();
        std::vector<std::uint8_t> pinned(n, 0);
        Points pinDv = Points::Zero(3, n);
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < n) {
                pinned[p.particle] = 1;
                pinDv.col(p.particle) = pinVelocityChange(p, state.x.col(p.particle), state.v.col(p.particle), h);
            }
        if (model.id() != modelId_ || h != h_ || env.drag != drag_ || pinned != pinned_) factor(model, env, h, pinned);
        computeForces(model, env, state, input.externalForce, force_);
        // b = h f - h^2 k L v, with pinned columns moved to the right-hand side.
        Eigen::MatrixXd b = (h * force_).transpose();  // n x 3
        for (const Spring& s : model.springs()) {
            const Vec3 lv = s.k * (state.v.col(s.j) - state.v.col(s.i));  // (k L v) on i is -k (v_j - v_i)
            b.row(s.i) += h2 * lv.transpose();
            b.row(s.j) -= h2 * lv.transpose();
            if (pinned[s.j]) b.row(s.i) += h2 * s.k * pinDv.col(s.j).transpose();
            if (pinned[s.i]) b.row(s.j) += h2 * s.k * pinDv.col(s.i).transpose();
        }
        for (Index i = 0; i < n; ++i)
            if (pinned[i]) b.row(i) = pinDv.col(i).transpose();
        profile_.forcesMs = msSince(t0);
        t0 = Clock::now();
        const Eigen::MatrixXd dv = chol_.solve(b);
        dv_ = dv.transpose();
        profile_.solveMs = msSince(t0);
        if (chol_.info() != Eigen::Success || !dv_.allFinite()) return {StepStatus::SolverFailed, -1};
        t0 = Clock::now();
        scratch_.v = state.v + dv_;
        scratch_.x = state.x + h * scratch_.v;
        StepResult r = commitStep(model, constraints_, input, *pool_, state, scratch_, StepResult{});
        profile_.integrateMs = msSince(t0);
        return r;
    }

private:
    void factor(const Model& model, const Environment& env, Scalar h, const std::vector<std::uint8_t>& pinned) {
        const Index n = model.particleCount();
        std::vector<Eigen::Triplet<Scalar>> t;
        for (Index i = 0; i < n; ++i)
            t.emplace_back(i, i, pinned[i] ? 1.0 : model.masses()[i] * (1 + h * env.drag));
        for (const Spring& s : model.springs()) {
            const Scalar w = h * h * s.k;
            if (!pinned[s.i]) t.emplace_back(s.i, s.i, w);
            if (!pinned[s.j]) t.emplace_back(s.j, s.j, w);
            if (!pinned[s.i] && !pinned[s.j]) {
                t.emplace_back(s.i, s.j, -w);
                t.emplace_back(s.j, s.i, -w);
            }
        }
        Eigen::SparseMatrix<Scalar> A(n, n);
        A.setFromTriplets(t.begin(), t.end());
        chol_.compute(A);
        modelId_ = model.id();
        h_ = h;
        drag_ = env.drag;
        pinned_ = pinned;
    }
    Eigen::SimplicialLLT<Eigen::SparseMatrix<Scalar>> chol_;
    std::uint64_t modelId_ = 0;
    Scalar h_ = 0, drag_ = 0;
    std::vector<std::uint8_t> pinned_;
    Points force_;
    State scratch_;
};

}  // namespace

FLAGSIM_SOLVER_KIND(desbrun) {
    return {"desbrun", "Desbrun, Schroder & Barr 1999: constant isotropic Jacobian, factored once",
            defaultsTo<DesbrunSettings>, withCommon({}, false), {}, createSolver<DesbrunSolver>};
}

}  // namespace cloth
