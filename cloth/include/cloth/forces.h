#pragma once
// Spring force and Jacobian kernels (Kang & Cho eqs. 15-17), and the energies they derive from.
// Pure functions of their arguments; the step loops over springs and calls them.

#include <cmath>

#include "cloth/model.h"

namespace cloth {

// Below this length a spring has no defined direction: force and Jacobian are zero.
constexpr Scalar kMinSpringLength = 1e-12;

// Eqs. 15-17 for one spring with d = x_j - x_i, as six numbers: the direction u = d / L, the
// Jacobian J_ij = df_i/dx_j = a I + b u u^T with a = k (1 - l0/L), b = k l0/L (eq. 16), and the
// force magnitude fm = k (L - l0), so that f_i = fm u (eq. 15). Eq. 17 (compressionRule): under
// compression (L < l0) the Jacobian uses l0 := L, so a = 0 and J = k u u^T is positive
// semi-definite; the force keeps the true l0. A spring shorter than kMinSpringLength has no
// direction: all six are zero. Written without branches so that the fast paths' loops over
// springs vectorize; every path of the library computes its springs here.
template <class T>
struct SpringTerms {
    T ux, uy, uz, a, b, fm;
};

template <class T>
[[gnu::always_inline]] inline SpringTerms<T> springTerms(T dx, T dy, T dz, T k, T rest, bool compressionRule) {
    const T L = std::sqrt(dx * dx + dy * dy + dz * dz);
    const bool live = L >= T(kMinSpringLength);
    const T inv = live ? T(1) / (live ? L : T(1)) : T(0);
    const T r = rest * inv;
    const T ratio = compressionRule ? (r > T(1) ? T(1) : r) : r;
    return {dx * inv, dy * inv, dz * inv, live ? k * (T(1) - ratio) : T(0), k * ratio, live ? k * (L - rest) : T(0)};
}

inline SpringTerms<Scalar> springTerms(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest, bool compressionRule) {
    const Vec3 d = xj - xi;
    return springTerms(d.x(), d.y(), d.z(), k, rest, compressionRule);
}

// Eq. 15: force on particle i from spring (i, j): f_i = k (L - l0) u, u = (x_j - x_i) / L.
inline Vec3 springForce(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest) {
    const SpringTerms<Scalar> t = springTerms(xi, xj, k, rest, false);
    return t.fm * Vec3(t.ux, t.uy, t.uz);
}

// E = k/2 (L - l0)^2, so that springForce = -dE/dx_i.
inline Scalar springEnergy(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest) {
    const Scalar s = (xj - xi).norm() - rest;
    return Scalar(0.5) * k * s * s;
}

// Eqs. 16, 17: J_ij = df_i/dx_j = a I + b u u^T; J_ii = -sum_j J_ij.
inline Mat3 springJacobian(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest, bool compressionRule) {
    const SpringTerms<Scalar> t = springTerms(xi, xj, k, rest, compressionRule);
    const Vec3 u(t.ux, t.uy, t.uz);
    return t.a * Mat3::Identity() + t.b * (u * u.transpose());
}

}  // namespace cloth
