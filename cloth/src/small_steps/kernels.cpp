#include "small_steps/kernels.h"

#include <cmath>

#include "cloth/forces.h"
#include "simd.h"

namespace cloth {

namespace {

CLOTH_SIMD_CLONES void springLoop(const float* __restrict x, const float* __restrict y, const float* __restrict z,
                                  int d, const float* __restrict k, const float* __restrict rest,
                                  float* __restrict fx, float* __restrict fy, float* __restrict fz, int begin, int end) {
    const float minLength = float(kMinSpringLength);
CLOTH_IVDEP
    for (int p = begin; p < end; ++p) {
        const float dx = x[p + d] - x[p], dy = y[p + d] - y[p], dz = z[p + d] - z[p];
        const float L = std::sqrt(dx * dx + dy * dy + dz * dz);
        const bool live = L >= minLength;
        const float c = live ? k[p] * (L - rest[p]) / (live ? L : 1.0f) : 0.0f;
        fx[p] = c * dx, fy[p] = c * dy, fz[p] = c * dz;
    }
}

struct AirLoopArgs {
    const float *x, *y, *z, *vx, *vy, *vz, *valid, *even;
    float* c[4][3];  // corner, axis
    int nx;
};

// One triangle's share (air.h): N = (b - a) x (c - a), w = wind - mean corner velocity,
// F / 3 = scale [normal s q / |N| N + (friction s |N| - lift q^2 / (|N| s)) w], q = w . N.
CLOTH_INLINE inline void triangleShare(const AirConstants& a, float ex, float ey, float ez, float gx, float gy, float gz,
                                       float wx, float wy, float wz, float& sx, float& sy, float& sz) {
    const float nx = ey * gz - ez * gy, ny = ez * gx - ex * gz, nz = ex * gy - ey * gx;
    const float twiceArea = std::sqrt(nx * nx + ny * ny + nz * nz);
    const float s = std::sqrt(wx * wx + wy * wy + wz * wz);
    const float q = wx * nx + wy * ny + wz * nz;
    const bool none = twiceArea < 1e-14f || s < 1e-9f;
    const float inv = 1.0f / (none ? 1.0f : twiceArea * s);
    const float cn = a.normal * s * s * q * inv, cw = a.friction * s * twiceArea - a.lift * q * q * inv;
    sx = none ? 0.0f : a.scale * (cn * nx + cw * wx);
    sy = none ? 0.0f : a.scale * (cn * ny + cw * wy);
    sz = none ? 0.0f : a.scale * (cn * nz + cw * wz);
}

// A value of corner c1 or a2 (stencil_cloth.h): both candidates load contiguously, a select
// picks one per lane (an index chosen per lane would be a gather).
CLOTH_INLINE inline float pick(bool even, float onEven, float onOdd) { return even ? onEven : onOdd; }

CLOTH_SIMD_CLONES void airLoop(const AirConstants& air, const AirLoopArgs& a, int begin, int end) {
    const float *__restrict x = a.x, *__restrict y = a.y, *__restrict z = a.z;
    const float *__restrict vx = a.vx, *__restrict vy = a.vy, *__restrict vz = a.vz;
    const int W = a.nx;
CLOTH_IVDEP
    for (int p = begin; p < end; ++p) {
        const bool even = a.even[p] != 0.0f, valid = a.valid[p] != 0.0f;
        const int e = p + 1, s = p + W, d = p + W + 1;
        // Triangle 1: {p, s, c1}, c1 = d on an even quad, e on an odd one; triangle 2: {a2, e, d},
        // a2 = p on an even quad, s on an odd one (stencil_cloth.h).
        const float c1x = pick(even, x[d], x[e]), c1y = pick(even, y[d], y[e]), c1z = pick(even, z[d], z[e]);
        const float c1vx = pick(even, vx[d], vx[e]), c1vy = pick(even, vy[d], vy[e]), c1vz = pick(even, vz[d], vz[e]);
        const float a2x = pick(even, x[p], x[s]), a2y = pick(even, y[p], y[s]), a2z = pick(even, z[p], z[s]);
        const float a2vx = pick(even, vx[p], vx[s]), a2vy = pick(even, vy[p], vy[s]), a2vz = pick(even, vz[p], vz[s]);
        float s1x, s1y, s1z, s2x, s2y, s2z;
        triangleShare(air, x[s] - x[p], y[s] - y[p], z[s] - z[p], c1x - x[p], c1y - y[p], c1z - z[p],
                      air.windX - (vx[p] + vx[s] + c1vx) / 3, air.windY - (vy[p] + vy[s] + c1vy) / 3,
                      air.windZ - (vz[p] + vz[s] + c1vz) / 3, s1x, s1y, s1z);
        triangleShare(air, x[e] - a2x, y[e] - a2y, z[e] - a2z, x[d] - a2x, y[d] - a2y, z[d] - a2z,
                      air.windX - (a2vx + vx[e] + vx[d]) / 3, air.windY - (a2vy + vy[e] + vy[d]) / 3,
                      air.windZ - (a2vz + vz[e] + vz[d]) / 3, s2x, s2y, s2z);
        const float s1[3] = {s1x, s1y, s1z}, s2[3] = {s2x, s2y, s2z};
        for (int axis = 0; axis < 3; ++axis) {
            const float both = s1[axis] + s2[axis];
            a.c[0][axis][p] = valid ? pick(even, both, s1[axis]) : 0.0f;  // corner p
            a.c[1][axis][p] = valid ? pick(even, s2[axis], both) : 0.0f;  // corner e
            a.c[2][axis][p] = valid ? pick(even, s1[axis], both) : 0.0f;  // corner s
            a.c[3][axis][p] = valid ? pick(even, both, s2[axis]) : 0.0f;  // corner d
        }
    }
}

struct IntegrateLoopArgs {
    float *x, *y, *z, *vx, *vy, *vz;
    const float* invMass;
    const float* spring[8][3];  // per family, per axis
    int d[8];
    int families;
    const float* corner[4][3];
    int nx;
};

// The force on each particle of [begin, end) into (fx, fy, fz), after the base force there.
CLOTH_INLINE inline void addSprings(const IntegrateLoopArgs& a, float* __restrict fx, float* __restrict fy,
                                    float* __restrict fz, int begin, int n) {
    for (int f = 0; f < a.families; ++f) {
        const int d = a.d[f];
        const float *__restrict lx = a.spring[f][0] + begin, *__restrict ly = a.spring[f][1] + begin,
                                *__restrict lz = a.spring[f][2] + begin;
        const float *__restrict ux = lx - d, *__restrict uy = ly - d, *__restrict uz = lz - d;
        for (int t = 0; t < n; ++t) fx[t] += lx[t] - ux[t], fy[t] += ly[t] - uy[t], fz[t] += lz[t] - uz[t];
    }
}

// The air of corner c of quad p - shift for each particle p: corner c of the quad is the particle.
CLOTH_INLINE inline void addCorner(const float* const* corner, int shift, float* __restrict fx, float* __restrict fy,
                                   float* __restrict fz, int begin, int n) {
    const float *__restrict cx = corner[0] + begin - shift, *__restrict cy = corner[1] + begin - shift,
                            *__restrict cz = corner[2] + begin - shift;
    for (int t = 0; t < n; ++t) fx[t] += cx[t], fy[t] += cy[t], fz[t] += cz[t];
}

CLOTH_INLINE inline void addAir(const IntegrateLoopArgs& a, float* __restrict fx, float* __restrict fy,
                                float* __restrict fz, int begin, int n) {
    addCorner(a.corner[0], 0, fx, fy, fz, begin, n);
    addCorner(a.corner[1], 1, fx, fy, fz, begin, n);
    addCorner(a.corner[2], a.nx, fx, fy, fz, begin, n);
    addCorner(a.corner[3], a.nx + 1, fx, fy, fz, begin, n);
}

CLOTH_SIMD_CLONES void integrateLoop(const IntegrateConstants& c, const IntegrateLoopArgs& a, int begin, int end) {
    alignas(64) float fx[kTile], fy[kTile], fz[kTile];
    for (int first = begin; first < end; first += kTile) {
        const int n = first + kTile < end ? kTile : end - first;
        for (int t = 0; t < n; ++t) fx[t] = fy[t] = fz[t] = 0.0f;
        addSprings(a, fx, fy, fz, first, n);
        if (c.air) addAir(a, fx, fy, fz, first, n);
        if (c.extX) {
            const float *__restrict ex = c.extX + first, *__restrict ey = c.extY + first, *__restrict ez = c.extZ + first;
            for (int t = 0; t < n; ++t) fx[t] += ex[t], fy[t] += ey[t], fz[t] += ez[t];
        }
        // x and v are read and written at the same index only; every pin value is loaded, a
        // select keeps it for a pinned particle (a conditional load would keep the loop scalar).
        float *x = a.x + first, *y = a.y + first, *z = a.z + first;
        float *vx = a.vx + first, *vy = a.vy + first, *vz = a.vz + first;
        const float *__restrict im = a.invMass + first, *__restrict pin = c.pinned + first;
        const float *__restrict px = c.pinX + first, *__restrict py = c.pinY + first, *__restrict pz = c.pinZ + first;
        const float *__restrict pvx = c.pinVX + first, *__restrict pvy = c.pinVY + first, *__restrict pvz = c.pinVZ + first;
        const float h = c.h, gx = c.gx, gy = c.gy, gz = c.gz, drag = c.drag;
CLOTH_IVDEP
        for (int t = 0; t < n; ++t) {
            const bool pinned = pin[t] != 0.0f;
            // a = g - drag v + f / m
            const float ax = gx - drag * vx[t] + fx[t] * im[t], ay = gy - drag * vy[t] + fy[t] * im[t],
                        az = gz - drag * vz[t] + fz[t] * im[t];
            const float nvx = vx[t] + h * ax, nvy = vy[t] + h * ay, nvz = vz[t] + h * az;
            const float nx = x[t] + h * nvx, ny = y[t] + h * nvy, nz = z[t] + h * nvz;
            const float qx = px[t], qy = py[t], qz = pz[t], wx = pvx[t], wy = pvy[t], wz = pvz[t];
            x[t] = pinned ? qx : nx, y[t] = pinned ? qy : ny, z[t] = pinned ? qz : nz;
            vx[t] = pinned ? wx : nvx, vy[t] = pinned ? wy : nvy, vz[t] = pinned ? wz : nvz;
        }
    }
}

constexpr int kMaxLanes = 16;

CLOTH_INLINE inline float larger(float most, float d) { return most < d ? d : most; }  // std::max's choice

CLOTH_SIMD_CLONES float fastestLoop(const float* __restrict vx, const float* __restrict vy, const float* __restrict vz,
                                    float px, float py, float pz, int begin, int end) {
    auto squared = [&](int i) {  // |v_i - pole|^2
        const float dx = vx[i] - px, dy = vy[i] - py, dz = vz[i] - pz;
        return dx * dx + dy * dy + dz * dz;
    };
    float lanes[kMaxLanes] = {};
    int i = begin;
    for (; i + kMaxLanes <= end; i += kMaxLanes)
        for (int l = 0; l < kMaxLanes; ++l) lanes[l] = larger(lanes[l], squared(i + l));
    float most = 0;
    for (int l = 0; l < kMaxLanes; ++l) most = larger(most, lanes[l]);
    for (; i < end; ++i) most = larger(most, squared(i));
    return most;
}

}  // namespace

float fastestSquaredKernel(const float* vx, const float* vy, const float* vz, const float pole[3], int begin, int end) {
    return fastestLoop(vx, vy, vz, pole[0], pole[1], pole[2], begin, end);
}

void springKernel(const StencilCloth& cloth, int f, StencilState& s, int begin, int end) {
    springLoop(s.x.x.at(), s.x.y.at(), s.x.z.at(), cloth.offsets[std::size_t(f)], cloth.k[std::size_t(f)].at(),
               cloth.rest[std::size_t(f)].at(), s.spring[std::size_t(f)].x.at(), s.spring[std::size_t(f)].y.at(),
               s.spring[std::size_t(f)].z.at(), begin, end);
}

void airKernel(const StencilCloth& cloth, const AirConstants& air, StencilState& s, int begin, int end) {
    AirLoopArgs a{s.x.x.at(), s.x.y.at(), s.x.z.at(), s.v.x.at(), s.v.y.at(), s.v.z.at(),
                  cloth.quadValid.at(), cloth.quadEven.at(), {}, cloth.nx};
    for (int c = 0; c < 4; ++c) a.c[c][0] = s.corner[c].x.at(), a.c[c][1] = s.corner[c].y.at(), a.c[c][2] = s.corner[c].z.at();
    airLoop(air, a, begin, end);
}

void integrateKernel(const StencilCloth& cloth, const IntegrateConstants& c, StencilState& s, int begin, int end) {
    IntegrateLoopArgs a{s.x.x.at(), s.x.y.at(), s.x.z.at(), s.v.x.at(), s.v.y.at(), s.v.z.at(), cloth.invMass.at(),
                        {}, {}, int(cloth.offsets.size()), {}, cloth.nx};
    for (std::size_t f = 0; f < cloth.offsets.size(); ++f) {
        a.spring[f][0] = s.spring[f].x.at(), a.spring[f][1] = s.spring[f].y.at(), a.spring[f][2] = s.spring[f].z.at();
        a.d[f] = cloth.offsets[f];
    }
    for (int k = 0; k < 4; ++k)
        a.corner[k][0] = s.corner[k].x.at(), a.corner[k][1] = s.corner[k].y.at(), a.corner[k][2] = s.corner[k].z.at();
    integrateLoop(c, a, begin, end);
}

}  // namespace cloth
