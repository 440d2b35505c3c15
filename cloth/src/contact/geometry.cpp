#include "contact/geometry.h"

#include <algorithm>
#include <cmath>

#include "simd.h"

namespace cloth::contact {

SegmentPair closestSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
    // Ericson 5.1.9: minimize |p0 + s d1 - q0 - t d2|^2 over the unit square.
    const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const Scalar a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    constexpr Scalar tiny = 1e-30;
    Scalar s = 0, t = 0;
    if (a <= tiny && e <= tiny) {
        s = t = 0;
    } else if (a <= tiny) {
        t = std::clamp(f / e, Scalar(0), Scalar(1));
    } else {
        const Scalar c = d1.dot(r);
        if (e <= tiny) {
            s = std::clamp(-c / a, Scalar(0), Scalar(1));
        } else {
            const Scalar b = d1.dot(d2), denom = a * e - b * b;
            s = denom > tiny * a * e ? std::clamp((b * f - c * e) / denom, Scalar(0), Scalar(1)) : 0;
            t = (b * s + f) / e;
            if (t < 0) t = 0, s = std::clamp(-c / a, Scalar(0), Scalar(1));
            else if (t > 1) t = 1, s = std::clamp((b - c) / a, Scalar(0), Scalar(1));
        }
    }
    return {s, t, (p0 + s * d1 - q0 - t * d2).norm()};
}

PointTriangle closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const Scalar d1 = ab.dot(ap), d2 = ac.dot(ap);
    auto at = [&](Scalar u, Scalar v, Scalar w) { return PointTriangle{Vec3(u, v, w), (p - (u * a + v * b + w * c)).norm()}; };
    if (d1 <= 0 && d2 <= 0) return at(1, 0, 0);
    const Vec3 bp = p - b;
    const Scalar d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return at(0, 1, 0);
    const Scalar vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const Scalar v = d1 / (d1 - d3);
        return at(1 - v, v, 0);
    }
    const Vec3 cp = p - c;
    const Scalar d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return at(0, 0, 1);
    const Scalar vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const Scalar w = d2 / (d2 - d6);
        return at(1 - w, 0, w);
    }
    const Scalar va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const Scalar w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return at(0, 1 - w, w);
    }
    const Scalar denom = 1 / (va + vb + vc);
    const Scalar v = vb * denom, w = vc * denom;
    return at(1 - v - w, v, w);
}

Scalar pointBoxDistance(const Vec3& p, const Vec3& center, const Mat3& R, const Vec3& e) {
    const Vec3 local = R.transpose() * (p - center);
    return (local.cwiseAbs() - e).cwiseMax(0).norm();
}

Scalar segmentBoxDistance(const Vec3& p0, const Vec3& p1, const Vec3& center, const Mat3& R, const Vec3& e) {
    auto f = [&](Scalar t) { return pointBoxDistance(p0 + t * (p1 - p0), center, R, e); };
    constexpr Scalar g = 0.6180339887498949;
    Scalar lo = 0, hi = 1, x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
    for (int k = 0; k < 40; ++k) {
        if (f1 <= f2) hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = f(x1);
        else lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = f(x2);
    }
    const Scalar best = std::min({f(0), f(1), f1, f2});
    return std::max(Scalar(0), best - (hi - lo) * (p1 - p0).norm());
}

namespace {

CLOTH_SIMD_CLONES void lengthLoop(const Scalar* __restrict a, const Scalar* __restrict b, Index n, Scalar* __restrict out) {
CLOTH_IVDEP
    for (Index i = 0; i < n; ++i) {
        const Scalar dx = b[3 * i] - a[3 * i], dy = b[3 * i + 1] - a[3 * i + 1], dz = b[3 * i + 2] - a[3 * i + 2];
        out[i] = std::sqrt(dx * dx + dy * dy + dz * dz);
    }
}

}  // namespace

void moveLengths(const Points& y0, const Points& y1, std::vector<Scalar>& out, ParallelFor* loops) {
    out.resize(std::size_t(y0.cols()));
    forChunks(loops, int(y0.cols()), [&](int begin, int end) {
        lengthLoop(y0.data() + 3 * begin, y1.data() + 3 * begin, end - begin, out.data() + begin);
    });
}

}  // namespace cloth::contact
