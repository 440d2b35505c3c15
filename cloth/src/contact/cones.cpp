#include "contact/cones.h"

#include <algorithm>
#include <cmath>

#include "simd.h"

namespace cloth::contact {

namespace {

// Triangle t's edges a = m[b[t]] - m[a[t]] and b = m[c[t]] - m[a[t]] at the midpoints m, their
// ends' reaches da and db; n = a x b, e = da |b| + |a| db + da db, len = |n|: flipped (every
// direction) where e >= len, else axis n / len and cosHalf sqrt(1 - (e / len)^2).
CLOTH_SIMD_CLONES void coneLoop(const ConeScratch& s, const Scalar* __restrict reach, const Corners& tri, int begin,
                                int end, Scalar* __restrict x, Scalar* __restrict y, Scalar* __restrict z,
                                Scalar* __restrict cosHalf) {
    const Scalar *__restrict mx = s.mx.data(), *__restrict my = s.my.data(), *__restrict mz = s.mz.data();
    const Index *__restrict i0 = tri.a.data(), *__restrict i1 = tri.b.data(), *__restrict i2 = tri.c.data();
CLOTH_IVDEP
    for (int t = begin; t < end; ++t) {
        const Index p = i0[t], q = i1[t], r = i2[t];
        const Scalar ax = mx[q] - mx[p], ay = my[q] - my[p], az = mz[q] - mz[p];
        const Scalar bx = mx[r] - mx[p], by = my[r] - my[p], bz = mz[r] - mz[p];
        const Scalar da = reach[p] + reach[q], db = reach[p] + reach[r];
        const Scalar nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
        const Scalar an = std::sqrt(ax * ax + ay * ay + az * az);
        const Scalar bn = std::sqrt(bx * bx + by * by + bz * bz);
        const Scalar e = da * bn + an * db + da * db;
        const Scalar len = std::sqrt(nx * nx + ny * ny + nz * nz);
        const bool flips = e >= len;
        const Scalar safe = flips ? Scalar(1) : len;
        const Scalar sine = flips ? Scalar(0) : e / safe;
        x[t] = flips ? Scalar(0) : nx / safe;
        y[t] = flips ? Scalar(0) : ny / safe;
        z[t] = flips ? Scalar(1) : nz / safe;
        cosHalf[t] = flips ? Scalar(-1) : std::sqrt(1 - sine * sine);
    }
}

// widestCos of each cone (c, cc) to its group's axis (u).
CLOTH_SIMD_CLONES void widestLoop(const Cones& c, const ConeScratch& s, int begin, int end, Scalar* __restrict widest) {
    const Scalar *__restrict cx = c.x.data(), *__restrict cy = c.y.data(), *__restrict cz = c.z.data();
    const Scalar *__restrict ux = s.ux.data(), *__restrict uy = s.uy.data(), *__restrict uz = s.uz.data();
    const Scalar* __restrict cc = c.cosHalf.data();
CLOTH_IVDEP
    for (int k = begin; k < end; ++k) widest[k] = widestCos(cx[k] * ux[k] + cy[k] * uy[k] + cz[k] * uz[k], cc[k]);
}

}  // namespace

void mergeCones(const Vec3& a, Scalar ca, const Vec3& b, Scalar cb, Vec3& axis, Scalar& cosHalf) {
    const Vec3 sum = a + b;
    const Scalar norm = sum.norm();
    if (norm < 1e-12 || ca <= -1 || cb <= -1) {
        axis = Vec3::UnitZ(), cosHalf = -1;
        return;
    }
    axis = sum / norm;  // normalized(), without its second square root
    cosHalf = std::min(widestCos(a.dot(axis), ca), widestCos(b.dot(axis), cb));
}

Scalar partnerCos(Scalar cc, Scalar flat) {
    if (!(cc > flat)) return 2;
    const Scalar c = flat * cc + std::sqrt(1 - flat * flat) * std::sqrt(std::max(Scalar(0), 1 - cc * cc));
    return 2 * c * c - 1;
}

bool mergedWithin(const Vec3& a, Scalar ca, Scalar pa, const Vec3& b, Scalar cb, Scalar pb, Scalar flat) {
    if (ca > flat && cb > flat) {
        const Scalar d = a.dot(b), bound = std::max(pa, pb);
        if (d > bound + kDecided) return true;
        if (d < bound - kDecided) return false;
    }
    Vec3 axis;
    Scalar cosHalf = -1;
    mergeCones(a, ca, b, cb, axis, cosHalf);
    return cosHalf > flat;
}

void motionCones(const Points& y0, const Points& y1, const std::vector<Scalar>& reach, const Corners& triangles,
                 ConeScratch& s, Cones& out, ParallelFor* loops) {
    const std::size_t particles = std::size_t(y0.cols());
    for (auto* v : {&s.mx, &s.my, &s.mz}) v->resize(particles);
    forChunks(loops, int(particles), [&](int begin, int end) {
        const Scalar *p0 = y0.data() + 3 * begin, *p1 = y1.data() + 3 * begin;
        for (std::size_t i = std::size_t(begin); i < std::size_t(end); ++i, p0 += 3, p1 += 3)
            s.mx[i] = 0.5 * (p0[0] + p1[0]), s.my[i] = 0.5 * (p0[1] + p1[1]), s.mz[i] = 0.5 * (p0[2] + p1[2]);
    });
    out.resize(triangles.size());
    forChunks(loops, int(triangles.size()), [&](int begin, int end) {
        coneLoop(s, reach.data(), triangles, begin, end, out.x.data(), out.y.data(), out.z.data(), out.cosHalf.data());
    });
}

void widestToAxes(const Cones& cones, const std::vector<std::size_t>& start, const std::vector<Vec3>& axes,
                  ConeScratch& s, std::vector<Scalar>& widest, ParallelFor* loops) {
    const std::size_t n = cones.cosHalf.size();
    for (auto* v : {&s.ux, &s.uy, &s.uz}) v->resize(n);
    widest.resize(n);
    forChunks(loops, int(start.size()) - 1, [&](int begin, int end) {
        for (std::size_t j = std::size_t(begin); j < std::size_t(end); ++j)
            for (std::size_t k = start[j]; k < start[j + 1]; ++k) s.ux[k] = axes[j].x(), s.uy[k] = axes[j].y(), s.uz[k] = axes[j].z();
        widestLoop(cones, s, int(start[std::size_t(begin)]), int(start[std::size_t(end)]), widest.data());
    });
}

}  // namespace cloth::contact
