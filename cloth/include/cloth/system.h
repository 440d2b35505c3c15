#pragma once
// The linearized backward Euler system of one step (Kang & Cho eqs. 1-7, 12), with pinned
// particles eliminated. Every solver in this library reads the same system, so "the same cloth,
// same masses, same pins" holds by construction.
//
//   (M + h C - h^2 J) dv = h f + h^2 J v      (C = -df/dv: linear drag, and implicit air)
// Rows of pinned particles become dv_p = prescribed; their columns move to the right-hand side.

#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "cloth/forces.h"
#include "cloth/model.h"
#include "cloth/parallel_for.h"

namespace cloth {

struct AirParams;  // air.h
struct Collider;   // collision.h

// A particle pinned to a target the caller moves: at the end of the step the particle sits
// exactly at x with velocity v.
struct Pin {
    Index particle = 0;
    Vec3 x = Vec3::Zero();
    Vec3 v = Vec3::Zero();
};

// Contact at a solver's own substeps (Solver::resolvesCollisions: small_steps): the solver calls
// apply after a substep's collisions, over the substeps since the last contact, from fraction
// `from` to `to` of the step: `xStart` the positions where they began, `state` where they ended
// (world, changed in place), h the last substep's length: a correction changes a velocity by
// correction / h, as a position-based step's velocity is its last move over its length.
// cloth::Cloth hands in its contact stage (contact.h) this way, so that a solver taking many
// substeps per step meets contact at every one, or every few, as the reference does at every one.
// `loops` (or null) runs the contact's parallel loops on the solver's threads, which wait for it.
class SubstepContact {
public:
    virtual ~SubstepContact() = default;
    virtual void apply(Scalar from, Scalar to, const Points& xStart, State& state, Scalar h, ParallelFor* loops) = 0;
    // Contact after every this many substeps (and after the last), over the motion since the last.
    virtual int stride() const { return 1; }
    // > 0: and only once the fastest particle has also moved this far relative to the pole since
    // the last contact (m; ContactSettings::strideMove).
    virtual Scalar strideMove() const { return 0; }
};

struct StepInput {
    Scalar h = Scalar(1) / 60;
    // Owned, not a view: `input.pins = pinColumn(model)` must not leave a dangling reference.
    std::vector<Pin> pins;
    const Points* externalForce = nullptr;  // per-particle external forces (air), or null
    // Per-particle C_i = -df_i/dv_i of the external force (symmetric positive semi-definite;
    // air.h's airDamping), or null. Implicit solvers add h C_i to W_ii, which integrates the
    // external force implicitly in velocity; null keeps it explicit.
    const std::vector<Mat3>* damping = nullptr;
    // The air, for a solver that evaluates it itself at the end-of-step state (Solver::couplesAir:
    // newton). Such a solver ignores `damping`; the caller then leaves the air out of
    // externalForce. Null for the others.
    const AirParams* air = nullptr;
    // The colliders, for a solver that meets them itself at every substep
    // (Solver::resolvesCollisions: small_steps), each particle kept `thickness` out of them and
    // those with collisionSkip[i] != 0 left alone (collision.h's resolveCollisions). Null for the
    // others: the caller resolves the collisions after the step.
    const std::vector<Collider>* colliders = nullptr;
    Scalar thickness = 0;
    const std::vector<std::uint8_t>* collisionSkip = nullptr;
    // Contact after every substep, for a solver that meets the colliders itself; null: none, or
    // the caller runs it after the step.
    SubstepContact* contact = nullptr;
};

// One implicit step's problem: the cloth, its environment, the state the step starts from, the
// step's input and the Jacobian rule (eq. 17). Every layer of an implicit step reads it; it holds
// references, so it lives no longer than what it names.
struct StepProblem {
    const Model& model;
    const Environment& env;
    const State& state;
    const StepInput& input;
    bool compressionRule = true;
};

struct LinearSystem {
    Scalar h = 0;
    std::vector<Mat3> springJ;   // J_ij per spring (eqs. 16, 17)
    std::vector<Mat3> diag;      // W_ii = m_i (1 + h c) I + h C_i + h^2 sum_j J_ij (eq. 12); I if pinned
    std::vector<Mat3> diagInv;   // W_ii^-1
    Points force;                // f at the current state
    Points rhs;                  // b_i = h f_i + h^2 sum_j J_ij (v_j - v_i) + h^2 sum_{j pinned} J_ij dv_j
    std::vector<std::uint8_t> pinned;
    Points pinDv;                // prescribed dv of pinned particles, zero elsewhere
};

// y_i = h^2 sum_{j free} J_ij x_j for free i; zero for pinned i. (The off-diagonal part of -W.)
void applyOffDiagonal(const Model& model, const LinearSystem& sys, const Points& x, Points& y);

// W as a sparse symmetric 3n x 3n matrix (pinned rows and columns are identity).
Eigen::SparseMatrix<Scalar> assembleMatrix(const Model& model, const LinearSystem& sys);

// Relative residual |W dv - b| / |b| (b with pinned entries set to their prescribed dv).
Scalar relativeResidual(const Model& model, const LinearSystem& sys, const Points& dv);

}  // namespace cloth
