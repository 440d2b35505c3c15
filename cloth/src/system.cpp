#include "cloth/system.h"

#include "cloth/forces.h"

namespace cloth {

void buildSystem(const Model& model, const Environment& env, const State& state,
                 const StepInput& input, bool compressionRule, LinearSystem& sys) {
    const Index n = model.particleCount();
    const Scalar h = input.h, h2 = h * h;
    const auto& springs = model.springs();
    const auto& mass = model.masses();
    sys.h = h;

    sys.pinned.assign(n, 0);
    sys.pinDv.setZero(3, n);
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= n) continue;
        sys.pinned[p.particle] = 1;
        // The velocity that carries the particle from x onto its target in one step.
        sys.pinDv.col(p.particle) = (p.x - state.x.col(p.particle)) / h - state.v.col(p.particle);
    }

    computeForces(model, env, state, input.externalForce, sys.force);

    // W_ii = m_i (1 + h c) I + h C_i + h^2 sum_j J_ij (eq. 12, with the implicit linear drag c
    // and the external force's damping C_i).
    sys.diag.resize(n);
    for (Index i = 0; i < n; ++i) {
        sys.diag[i] = mass[i] * (1 + h * env.drag) * Mat3::Identity();
        if (input.damping) sys.diag[i] += h * (*input.damping)[i];
    }
    // b_i = h f_i + h^2 sum_j J_ij (v_j - v_i)   (eq. 7: the viscous term folded into the force)
    //     + h^2 sum_{j pinned} J_ij dv_j         (pinned columns moved to the right-hand side)
    sys.rhs = h * sys.force;
    sys.springJ.resize(springs.size());
    for (std::size_t s = 0; s < springs.size(); ++s) {
        const Spring& sp = springs[s];
        const Mat3 J = springJacobian(state.x.col(sp.i), state.x.col(sp.j), sp.k, sp.rest,
                                      compressionRule);
        sys.springJ[s] = J;
        sys.diag[sp.i] += h2 * J;
        sys.diag[sp.j] += h2 * J;
        const Vec3 Jdv = h2 * (J * (state.v.col(sp.j) - state.v.col(sp.i)));
        sys.rhs.col(sp.i) += Jdv;
        sys.rhs.col(sp.j) -= Jdv;
        if (sys.pinned[sp.j]) sys.rhs.col(sp.i) += h2 * (J * sys.pinDv.col(sp.j));
        if (sys.pinned[sp.i]) sys.rhs.col(sp.j) += h2 * (J * sys.pinDv.col(sp.i));
    }
    sys.diagInv.resize(n);
    for (Index i = 0; i < n; ++i) {
        if (sys.pinned[i]) {
            sys.diag[i].setIdentity();
            sys.rhs.col(i) = sys.pinDv.col(i);
        }
        sys.diagInv[i] = sys.diag[i].inverse();
    }
}

void applyOffDiagonal(const Model& model, const LinearSystem& sys, const Points& x, Points& y) {
    const Scalar h2 = sys.h * sys.h;
    const auto& springs = model.springs();
    y.setZero(3, model.particleCount());
    for (std::size_t s = 0; s < springs.size(); ++s) {
        const Spring& sp = springs[s];
        const bool pi = sys.pinned[sp.i], pj = sys.pinned[sp.j];
        if (pi || pj) continue;  // pinned columns live in the right-hand side, pinned rows are fixed
        y.col(sp.i) += h2 * (sys.springJ[s] * x.col(sp.j));
        y.col(sp.j) += h2 * (sys.springJ[s] * x.col(sp.i));
    }
}

Eigen::SparseMatrix<Scalar> assembleMatrix(const Model& model, const LinearSystem& sys) {
    const Index n = model.particleCount();
    const Scalar h2 = sys.h * sys.h;
    std::vector<Eigen::Triplet<Scalar>> t;
    t.reserve(9 * (n + 2 * model.springs().size()));
    auto block = [&t](Index bi, Index bj, const Mat3& B) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) t.emplace_back(3 * bi + r, 3 * bj + c, B(r, c));
    };
    for (Index i = 0; i < n; ++i) block(i, i, sys.diag[i]);
    const auto& springs = model.springs();
    for (std::size_t s = 0; s < springs.size(); ++s) {
        const Spring& sp = springs[s];
        if (sys.pinned[sp.i] || sys.pinned[sp.j]) continue;
        const Mat3 W = -h2 * sys.springJ[s];  // W_ij = -h^2 J_ij
        block(sp.i, sp.j, W);
        block(sp.j, sp.i, W.transpose());
    }
    Eigen::SparseMatrix<Scalar> W(3 * n, 3 * n);
    W.setFromTriplets(t.begin(), t.end());
    return W;
}

Scalar relativeResidual(const Model& model, const LinearSystem& sys, const Points& dv) {
    Points off;
    applyOffDiagonal(model, sys, dv, off);
    Scalar r2 = 0, b2 = 0;
    for (Index i = 0; i < model.particleCount(); ++i) {
        const Vec3 r = sys.diag[i] * dv.col(i) - off.col(i) - sys.rhs.col(i);
        r2 += r.squaredNorm();
        b2 += sys.rhs.col(i).squaredNorm();
    }
    return b2 > 0 ? std::sqrt(r2 / b2) : std::sqrt(r2);
}

}  // namespace cloth
