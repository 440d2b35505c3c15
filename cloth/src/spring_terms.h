#pragma once
// The spring terms of eqs. 15-17, which every path of the library computes its springs with
// (forces.cpp, and through kernels.h the implicit step's layouts). Plain inline functions.

#include <cmath>

#include "cloth/model.h"

namespace cloth {

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

// J = a I + b u u^T of a spring's terms, as 6 numbers (xx xy xz yy yz zz).
template <class T>
[[gnu::always_inline]] inline void jacobianOf(const SpringTerms<T>& t, T* J) {
    J[0] = t.a + t.b * t.ux * t.ux, J[1] = t.b * t.ux * t.uy, J[2] = t.b * t.ux * t.uz;
    J[3] = t.a + t.b * t.uy * t.uy, J[4] = t.b * t.uy * t.uz, J[5] = t.a + t.b * t.uz * t.uz;
}

inline SpringTerms<Scalar> springTerms(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest, bool compressionRule) {
    const Vec3 d = xj - xi;
    return springTerms(d.x(), d.y(), d.z(), k, rest, compressionRule);
}

}  // namespace cloth
