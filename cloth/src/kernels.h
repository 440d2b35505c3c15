#pragma once
// Formulas that every fast path of the implicit step shares (the reference path in system.cpp
// writes them with Eigen types; the tests compare the two). Plain functions over scalars.

#include <cmath>

#include "cloth/forces.h"

namespace cloth {

// Eqs. 15-17 for one spring with d = x_j - x_i: u = d / L, J = a I + b u u^T, force on i fm u.
//   a = k (1 - l0/L), b = k l0/L (eq. 16); eq. 17 clamps l0/L to 1 under compression.
template <class T>
struct SpringTerms {
    T ux, uy, uz, a, b, fm;
};

template <class T>
inline SpringTerms<T> springTerms(T dx, T dy, T dz, T k, T rest, bool compressionRule) {
    const T L = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (L < T(kMinSpringLength)) return {T(0), T(0), T(0), T(0), T(0), T(0)};
    const T inv = T(1) / L;
    T ratio = rest * inv;
    if (compressionRule && ratio > T(1)) ratio = T(1);
    return {dx * inv, dy * inv, dz * inv, k * (T(1) - ratio), k * ratio, k * (L - rest)};
}

// Symmetric 3x3 matrices as 6 numbers: xx xy xz yy yz zz.
// y = S x
template <class T>
inline void symmetricTimes(const T* s, const T* x, T* y) {
    y[0] = s[0] * x[0] + s[1] * x[1] + s[2] * x[2];
    y[1] = s[1] * x[0] + s[3] * x[1] + s[4] * x[2];
    y[2] = s[2] * x[0] + s[4] * x[1] + s[5] * x[2];
}

// inv = S^-1 by cofactors; a singular S (zero determinant, as for a row with no unknown) gives
// inv = 0 and returns false.
template <class T>
inline bool symmetricInverse(const T* s, T* inv) {
    const T cxx = s[3] * s[5] - s[4] * s[4], cxy = s[2] * s[4] - s[1] * s[5], cxz = s[1] * s[4] - s[2] * s[3];
    const T cyy = s[0] * s[5] - s[2] * s[2], cyz = s[1] * s[2] - s[0] * s[4], czz = s[0] * s[3] - s[1] * s[1];
    const T det = s[0] * cxx + s[1] * cxy + s[2] * cxz;
    if (!(det != T(0))) {
        for (int k = 0; k < 6; ++k) inv[k] = T(0);
        return false;
    }
    const T id = T(1) / det;
    inv[0] = cxx * id, inv[1] = cxy * id, inv[2] = cxz * id, inv[3] = cyy * id, inv[4] = cyz * id, inv[5] = czz * id;
    return true;
}

}  // namespace cloth
