#pragma once
// The kernels every path of the implicit step shares (the paper's step in kangcho/paper_step.cpp,
// the gather and stencil layouts of kangcho, multigrid): the spring terms (spring_terms.h),
// symmetric 3x3 blocks (product, inverse) and the pin velocity change. Plain inline functions.

#include <algorithm>
#include <cmath>
#include <vector>

#include "cloth/system.h"
#include "spring_terms.h"

namespace cloth {

// Symmetric 3x3 matrices as 6 numbers: xx xy xz yy yz zz.
// y = S x
template <class T>
[[gnu::always_inline]] inline void symmetricTimes(const T* s, const T* x, T* y) {
    y[0] = s[0] * x[0] + s[1] * x[1] + s[2] * x[2];
    y[1] = s[1] * x[0] + s[3] * x[1] + s[4] * x[2];
    y[2] = s[2] * x[0] + s[4] * x[1] + s[5] * x[2];
}

// inv = S^-1 by cofactors; a singular S (zero determinant, as for a row with no unknown) gives
// inv = 0, and the result is false. Branch-free, so that loops over particles vectorize. V may be
// a pack (pack.h) of S: then the result is a lane mask.
template <class V, class S = V>
[[gnu::always_inline]] inline auto symmetricInverse(const V* s, V* inv) {
    const V cxx = s[3] * s[5] - s[4] * s[4], cxy = s[2] * s[4] - s[1] * s[5], cxz = s[1] * s[4] - s[2] * s[3];
    const V cyy = s[0] * s[5] - s[2] * s[2], cyz = s[1] * s[2] - s[0] * s[4], czz = s[0] * s[3] - s[1] * s[1];
    const V det = s[0] * cxx + s[1] * cxy + s[2] * cxz;
    const V zero{}, one = S(1) - zero;
    const auto regular = det != zero;
    const V id = regular ? S(1) / (regular ? det : one) : zero;
    inv[0] = cxx * id, inv[1] = cxy * id, inv[2] = cxz * id, inv[3] = cyy * id, inv[4] = cyz * id, inv[5] = czz * id;
    return regular;
}

// The same for a Mat3 (its upper triangle is read).
inline Mat3 symmetricInverse(const Mat3& S) {
    const Scalar s[6] = {S(0, 0), S(0, 1), S(0, 2), S(1, 1), S(1, 2), S(2, 2)};
    Scalar inv[6];
    symmetricInverse(s, inv);
    Mat3 out;
    out << inv[0], inv[1], inv[2], inv[1], inv[3], inv[4], inv[2], inv[4], inv[5];
    return out;
}

// The velocity change that carries a pinned particle from x (velocity v) onto its target in one
// step of length h: dv = (target - x) / h - v. Every implicit path prescribes it.
inline Vec3 pinVelocityChange(const Pin& pin, const Vec3& x, const Vec3& v, Scalar h) { return (pin.x - x) / h - v; }

// The step's pins: pinned[i] = 1 for each pinned particle (0 elsewhere) and its velocity change in
// dv[3 i .. 3 i + 2] (0 elsewhere), as T. Pins outside the model are ignored.
template <class T>
void gatherPins(const State& state, const StepInput& input, std::vector<unsigned char>& pinned, std::vector<T>& dv) {
    const Index n = Index(pinned.size());
    std::fill(pinned.begin(), pinned.end(), 0);
    std::fill(dv.begin(), dv.end(), T(0));
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= n) continue;
        pinned[p.particle] = 1;
        const Vec3 d = pinVelocityChange(p, state.x.col(p.particle), state.v.col(p.particle), input.h);
        for (int a = 0; a < 3; ++a) dv[3 * p.particle + a] = T(d[a]);
    }
}

}  // namespace cloth
