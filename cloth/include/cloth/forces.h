#pragma once
// Spring force and Jacobian kernels (Kang & Cho eqs. 15-17), and the energies they derive from:
// pure functions of their arguments; and the forces on the whole cloth (gravity, drag, springs).

#include <cmath>

#include "cloth/model.h"

namespace cloth {

struct Environment {
    Vec3 gravity = Vec3(0, -9.81, 0);  // m/s^2
    Scalar drag = 0;                   // linear drag rate, 1/s: f_i = -drag m_i v_i (implicit)
};

// Eq. 15: force on particle i from spring (i, j): f_i = k (L - l0) u, u = (x_j - x_i) / L.
// Zero for a spring shorter than kMinSpringLength.
Vec3 springForce(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest);

// E = k/2 (L - l0)^2, so that springForce = -dE/dx_i.
inline Scalar springEnergy(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest) {
    const Scalar s = (xj - xi).norm() - rest;
    return Scalar(0.5) * k * s * s;
}

// Eqs. 16, 17: J_ij = df_i/dx_j = k [ (1 - l0/L) I + (l0/L) u u^T ]; J_ii = -sum_j J_ij.
// Eq. 17 (compressionRule): under compression (L < l0) the Jacobian uses l0 := L, giving
// J_ij = k u u^T, which is positive semi-definite; the force keeps the true l0.
Mat3 springJacobian(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest, bool compressionRule);

// Gravity, drag, springs (eq. 15) and the external force, summed into f (3 x n).
void computeForces(const Model& model, const Environment& env, const State& state,
                   const Points* externalForce, Points& f);

}  // namespace cloth
