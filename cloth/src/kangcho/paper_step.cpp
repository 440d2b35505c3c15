// The paper's step (Kang & Cho), equation by equation: the linearized backward Euler system of
// one step, then dv(0) and the Jacobi sweeps. docs/algorithm.md explains each equation and lists
// what this library adds to the paper (pins, drag, implicit air). This is kangcho's
// impl=reference, and its system is the one exact, cg and chebyshev solve (buildSystem); the fast
// paths (kangcho/stencil.cpp, kangcho/gather.cpp) and multigrid compute the same numbers from the
// same kernels (kernels.h) in other layouts, and the tests compare them.

#include "cloth/paper_step.h"

#include "kernels.h"

namespace cloth {

namespace {

// The paper's step up to the system, and (when dv is given) the iterations on it.
void paperStep(const StepProblem& problem, int iterations, LinearSystem& sys, Points* dv) {
    const auto& [model, env, state, input, compressionRule] = problem;
    const Index n = model.particleCount();
    const Scalar h = input.h, h2 = h * h;
    const auto& springs = model.springs();
    const auto& mass = model.masses();
    sys.h = h;

    // Pins (an addition to the paper): a pinned particle's dv is prescribed, the one that lands
    // it on its target; its row leaves the system and its column moves to the right-hand side.
    sys.pinned.assign(n, 0);
    sys.pinDv.setZero(3, n);
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= n) continue;
        sys.pinned[p.particle] = 1;
        sys.pinDv.col(p.particle) = pinVelocityChange(p, state.x.col(p.particle), state.v.col(p.particle), h);
    }

    // f: gravity, linear drag, the external force (air), and the springs (eq. 15).
    computeForces(model, env, state, input.externalForce, sys.force);

    // Eq. 12: W_ii = m_i I + h^2 sum_j J_ij, here with the implicit linear drag, m_i h c I, and the
    // implicit air, h C_i. The spring part is added in the loop below.
    sys.diag.resize(n);
    for (Index i = 0; i < n; ++i) {
        sys.diag[i] = mass[i] * (1 + h * env.drag) * Mat3::Identity();
        if (input.damping) sys.diag[i] += h * (*input.damping)[i];
    }
    // Eq. 7: b_i = h f_i + h^2 sum_j J_ij (v_j - v_i), the viscous term folded into the force;
    // + h^2 sum_{j pinned} J_ij dv_j, the pinned columns.
    sys.rhs = h * sys.force;
    sys.springJ.resize(springs.size());
    for (std::size_t s = 0; s < springs.size(); ++s) {
        const Spring& sp = springs[s];
        // Eqs. 16, 17: J_ij = a I + b u u^T, positive semi-definite under compression.
        const Mat3 J = springJacobian(state.x.col(sp.i), state.x.col(sp.j), sp.k, sp.rest, compressionRule);
        sys.springJ[s] = J;
        sys.diag[sp.i] += h2 * J;  // eq. 12
        sys.diag[sp.j] += h2 * J;
        const Vec3 Jdv = h2 * (J * (state.v.col(sp.j) - state.v.col(sp.i)));  // eq. 7
        sys.rhs.col(sp.i) += Jdv;
        sys.rhs.col(sp.j) -= Jdv;
        if (sys.pinned[sp.j]) sys.rhs.col(sp.i) += h2 * (J * sys.pinDv.col(sp.j));
        if (sys.pinned[sp.i]) sys.rhs.col(sp.j) += h2 * (J * sys.pinDv.col(sp.i));
    }
    sys.diagInv.resize(n);
    for (Index i = 0; i < n; ++i) {
        if (sys.pinned[i]) {  // the pinned row: dv_p = prescribed
            sys.diag[i].setIdentity();
            sys.rhs.col(i) = sys.pinDv.col(i);
        }
        sys.diagInv[i] = symmetricInverse(sys.diag[i]);
    }
    if (!dv) return;

    // Eq. 11 with k = 0: dv(0)_i = W_ii^-1 b_i. (Eq. 14 writes its p_i for this dv(0).)
    jacobiStart(sys, *dv);
    // Eq. 11: dv(k+1)_i = W_ii^-1 (b_i + h^2 sum_j J_ij dv(k)_j); the first sweep from dv(0) is
    // eq. 14, the paper's step.
    Points next;
    for (int k = 0; k < iterations; ++k) {
        jacobiSweep(model, sys, *dv, next);
        std::swap(*dv, next);
    }
}

}  // namespace

void buildSystem(const StepProblem& problem, LinearSystem& sys) { paperStep(problem, 0, sys, nullptr); }

void paperStep(const StepProblem& problem, int iterations, LinearSystem& sys, Points& dv) {
    paperStep(problem, iterations, sys, &dv);
}

void jacobiStart(const LinearSystem& sys, Points& dv) {
    const Index n = static_cast<Index>(sys.diag.size());
    dv.resize(3, n);
    for (Index i = 0; i < n; ++i) dv.col(i) = sys.diagInv[i] * sys.rhs.col(i);
}

void jacobiSweep(const Model& model, const LinearSystem& sys, const Points& dv, Points& dvNext) {
    applyOffDiagonal(model, sys, dv, dvNext);  // dvNext_i = h^2 sum_j J_ij dv_j
    for (Index i = 0; i < model.particleCount(); ++i)
        dvNext.col(i) = sys.diagInv[i] * (sys.rhs.col(i) + dvNext.col(i));
}

}  // namespace cloth
