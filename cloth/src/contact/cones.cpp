#include "contact/cones.h"

#include <cmath>

#include "simd.h"

namespace cloth::contact {

namespace {

// n = a x b, e = da |b| + |a| db + da db, len = |n|: flipped (every direction) where e >= len,
// else axis n / len and cosHalf sqrt(1 - (e / len)^2).
CLOTH_SIMD_CLONES void coneLoop(const ConeScratch& s, int count, Scalar* __restrict x, Scalar* __restrict y,
                                Scalar* __restrict z, Scalar* __restrict cosHalf) {
    const Scalar *__restrict ax = s.ax.data(), *__restrict ay = s.ay.data(), *__restrict az = s.az.data();
    const Scalar *__restrict bx = s.bx.data(), *__restrict by = s.by.data(), *__restrict bz = s.bz.data();
    const Scalar *__restrict da = s.da.data(), *__restrict db = s.db.data();
CLOTH_IVDEP
    for (int t = 0; t < count; ++t) {
        const Scalar nx = ay[t] * bz[t] - az[t] * by[t], ny = az[t] * bx[t] - ax[t] * bz[t], nz = ax[t] * by[t] - ay[t] * bx[t];
        const Scalar an = std::sqrt(ax[t] * ax[t] + ay[t] * ay[t] + az[t] * az[t]);
        const Scalar bn = std::sqrt(bx[t] * bx[t] + by[t] * by[t] + bz[t] * bz[t]);
        const Scalar e = da[t] * bn + an * db[t] + da[t] * db[t];
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

// widestCos of each entry's cone axis (c) to its group's axis (u).
CLOTH_SIMD_CLONES void widestLoop(const ConeScratch& s, int count, Scalar* __restrict widest) {
    const Scalar *__restrict cx = s.cx.data(), *__restrict cy = s.cy.data(), *__restrict cz = s.cz.data();
    const Scalar *__restrict ux = s.ux.data(), *__restrict uy = s.uy.data(), *__restrict uz = s.uz.data();
    const Scalar* __restrict cc = s.cc.data();
CLOTH_IVDEP
    for (int k = 0; k < count; ++k) widest[k] = widestCos(cx[k] * ux[k] + cy[k] * uy[k] + cz[k] * uz[k], cc[k]);
}

}  // namespace

void motionCones(const Points& y0, const Points& y1, const std::vector<Scalar>& reach,
                 const std::vector<Triangle>& triangles, ConeScratch& s, Cones& out) {
    const std::size_t n = triangles.size(), particles = std::size_t(y0.cols());
    Scalar* m[3] = {nullptr, nullptr, nullptr};
    for (int axis = 0; axis < 3; ++axis) {
        std::vector<Scalar>& v = axis == 0 ? s.mx : axis == 1 ? s.my : s.mz;
        v.resize(particles), m[axis] = v.data();
        for (std::size_t i = 0; i < particles; ++i) v[i] = 0.5 * (y0(axis, Index(i)) + y1(axis, Index(i)));
    }
    for (auto* v : {&s.ax, &s.ay, &s.az, &s.bx, &s.by, &s.bz, &s.da, &s.db}) v->resize(n);
    Scalar* a[3] = {s.ax.data(), s.ay.data(), s.az.data()};
    Scalar* b[3] = {s.bx.data(), s.by.data(), s.bz.data()};
    for (std::size_t t = 0; t < n; ++t) {
        const Triangle& tri = triangles[t];
        for (int axis = 0; axis < 3; ++axis) {
            const Scalar m0 = m[axis][tri[0]];
            a[axis][t] = m[axis][tri[1]] - m0, b[axis][t] = m[axis][tri[2]] - m0;
        }
        s.da[t] = reach[tri[0]] + reach[tri[1]], s.db[t] = reach[tri[0]] + reach[tri[2]];
    }
    out.resize(n);
    coneLoop(s, int(n), out.x.data(), out.y.data(), out.z.data(), out.cosHalf.data());
}

void widestToAxes(const Cones& cones, const std::vector<Index>& order, const std::vector<std::size_t>& start,
                  const std::vector<Vec3>& axes, ConeScratch& s, std::vector<Scalar>& widest) {
    const std::size_t n = order.size();
    for (auto* v : {&s.cx, &s.cy, &s.cz, &s.cc, &s.ux, &s.uy, &s.uz}) v->resize(n);
    for (std::size_t j = 0; j + 1 < start.size(); ++j)
        for (std::size_t k = start[j]; k < start[j + 1]; ++k) {
            const Index t = order[k];
            s.cx[k] = cones.x[t], s.cy[k] = cones.y[t], s.cz[k] = cones.z[t], s.cc[k] = cones.cosHalf[t];
            s.ux[k] = axes[j].x(), s.uy[k] = axes[j].y(), s.uz[k] = axes[j].z();
        }
    widest.resize(n);
    widestLoop(s, int(n), widest.data());
}

}  // namespace cloth::contact
