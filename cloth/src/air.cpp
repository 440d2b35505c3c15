#include "cloth/air.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>

#include "cloth/parallel_for.h"
#include "simd.h"

namespace cloth {

namespace {

struct ShareArgs {
    const Triangle* triangles;
    const Scalar *x, *v;  // 3 x n, column-major
    Scalar windX, windY, windZ, scale, normal, friction, lift;
    Scalar *sx, *sy, *sz;  // per triangle
};

// Every triangle's share of its force (zero for a degenerate triangle or no relative air), written
// out per coordinate. Per tile of triangles, the corners' edges and the relative air are gathered
// into arrays, then the rest runs one triangle a SIMD lane, with a select in place of a branch.
CLOTH_SIMD_CLONES void triangleShares(const ShareArgs& a, Index begin, Index end) {
    const Scalar* __restrict x = a.x;
    const Scalar* __restrict v = a.v;
    alignas(64) Scalar ex[kTile], ey[kTile], ez[kTile], fx[kTile], fy[kTile], fz[kTile];
    alignas(64) Scalar wx[kTile], wy[kTile], wz[kTile];
    for (Index first = begin; first < end; first += kTile) {
        const int n = int(std::min<Index>(kTile, end - first));
        for (int t = 0; t < n; ++t) {
            const Triangle& tri = a.triangles[first + t];
            const std::size_t i = 3 * std::size_t(tri[0]), j = 3 * std::size_t(tri[1]), l = 3 * std::size_t(tri[2]);
            ex[t] = x[j] - x[i], ey[t] = x[j + 1] - x[i + 1], ez[t] = x[j + 2] - x[i + 2];
            fx[t] = x[l] - x[i], fy[t] = x[l + 1] - x[i + 1], fz[t] = x[l + 2] - x[i + 2];
            wx[t] = a.windX - (v[i] + v[j] + v[l]) / 3;
            wy[t] = a.windY - (v[i + 1] + v[j + 1] + v[l + 1]) / 3;
            wz[t] = a.windZ - (v[i + 2] + v[j + 2] + v[l + 2]) / 3;
        }
        Scalar *__restrict sx = a.sx + first, *__restrict sy = a.sy + first, *__restrict sz = a.sz + first;
CLOTH_IVDEP
        for (int t = 0; t < n; ++t) {
            const Scalar nx = ey[t] * fz[t] - ez[t] * fy[t], ny = ez[t] * fx[t] - ex[t] * fz[t],
                         nz = ex[t] * fy[t] - ey[t] * fx[t];
            const Scalar twiceArea = std::sqrt(nx * nx + ny * ny + nz * nz);
            const Scalar s = std::sqrt(wx[t] * wx[t] + wy[t] * wy[t] + wz[t] * wz[t]);
            const Scalar q = wx[t] * nx + wy[t] * ny + wz[t] * nz;
            const Scalar inv = 1 / (twiceArea * s);
            const Scalar cn = a.normal * s * s * q * inv, cw = a.friction * s * twiceArea - a.lift * q * q * inv;
            const bool none = twiceArea < 1e-14 || s < 1e-9;
            sx[t] = none ? 0 : a.scale * (cn * nx + cw * wx[t]);
            sy[t] = none ? 0 : a.scale * (cn * ny + cw * wy[t]);
            sz[t] = none ? 0 : a.scale * (cn * nz + cw * wz[t]);
        }
    }
}

// One triangle's share of -dF/dv (zero for a degenerate triangle or no relative air). With n fixed
// (it depends on x only), ds/dw = w^T / s and d(wn)/dw = n^T, the three terms' derivative is
//   dF/dw = a n n^T + b n w^T + c w n^T + d w w^T + e I
// with a = s (c_d - c_f + c_l), b = (c_d - c_f + c_l) wn / s, c = -2 c_l wn / s,
// d = c_f / s + c_l wn^2 / s^3, e = c_f s - c_l wn^2 / s; and f_i = F / 3, dw/dv_i = -I / 3.
Mat3 triangleBlock(const State& state, const Triangle& t, const Vec3& wind, const AirParams& air,
                   Scalar quarterRho) {
    const Vec3 p0 = state.x.col(t[0]), p1 = state.x.col(t[1]), p2 = state.x.col(t[2]);
    const Vec3 N = (p1 - p0).cross(p2 - p0);
    const Vec3 w = wind - (state.v.col(t[0]) + state.v.col(t[1]) + state.v.col(t[2])) / 3;
    const Scalar twiceArea = N.norm(), s = w.norm();
    if (twiceArea < 1e-14 || s < 1e-9) return Mat3::Zero();
    const Scalar c0 = quarterRho * twiceArea;  // 1/2 rho A
    const Scalar cd = c0 * air.dragCoefficient, cf = c0 * air.frictionCoefficient, cl = c0 * air.liftCoefficient;
    const Vec3 n = N / twiceArea;
    const Scalar wn = w.dot(n), normal = cd - cf + cl;
    const Scalar a = s * normal, b = normal * wn / s, c = -2 * cl * wn / s;
    const Scalar d = cf / s + cl * wn * wn / (s * s * s), e = cf * s - cl * wn * wn / s;
    Mat3 m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            m(i, j) = -(a * n[i] * n[j] + b * n[i] * w[j] + c * w[i] * n[j] + d * w[i] * w[j] + (i == j ? e : 0)) / 9;
    return m;
}

}  // namespace

void addAirForces(const Model& model, const State& state, const AirParams& air, Points& f,
                  std::vector<Mat3>* velocityJacobian, ThreadPool* pool, AirWorkspace* workspace) {
    // With N = (b - a) x (c - a) (|N| = 2 A, n = N / |N|) and q = w . N (wn = q / |N|), the three
    // terms of air.h add up to
    //   F = rho / 4 [(c_d - c_f + c_l) s q / |N| N + (c_f s |N| - c_l q^2 / (|N| s)) w]
    // with two square roots and one division, and no case on the side n faces: each term is even
    // in n (wn n, wn^2 and n n^T do not change when n flips).
    const Scalar quarterRho = Scalar(0.25) * air.density;
    const Scalar normal = air.dragCoefficient - air.frictionCoefficient + air.liftCoefficient;
    // Locals, not reads through `air`: the compiler cannot tell that the stores to f do not change it.
    const Vec3 wind = air.wind;
    const Scalar friction = air.frictionCoefficient, lift = air.liftCoefficient;
    const auto& triangles = model.triangles();
    const Index count = Index(triangles.size()), n = model.particleCount();
    // Every triangle's share (and block), then each particle's sum over its triangles in increasing
    // order: the bits of a loop over the triangles adding to their corners, whatever the threads,
    // and no two threads write one place.
    AirWorkspace local;
    AirWorkspace& ws = workspace ? *workspace : local;
    std::vector<Scalar>&shareX = ws.shareX, &shareY = ws.shareY, &shareZ = ws.shareZ;
    std::vector<Mat3>& blocks = ws.blocks;
    shareX.resize(count), shareY.resize(count), shareZ.resize(count);
    const ShareArgs args{triangles.data(), state.x.data(), state.v.data(), wind.x(), wind.y(), wind.z(),
                         quarterRho / 3, normal, friction, lift, shareX.data(), shareY.data(), shareZ.data()};
    forChunks(pool, count, [&](int begin, int end) { triangleShares(args, begin, end); });
    Mat3* jacobian = nullptr;
    const Mat3* block = nullptr;
    if (velocityJacobian) {
        velocityJacobian->assign(n, Mat3::Zero());
        jacobian = velocityJacobian->data();
        blocks.resize(count);
        Mat3* out = blocks.data();
        forChunks(pool, count, [&](int begin, int end) {
            for (Index k = begin; k < end; ++k) out[k] = triangleBlock(state, triangles[k], wind, air, quarterRho);
        });
        block = blocks.data();
    }
    const Index* start = model.triStart().data();
    const Index* of = model.triOf().data();
    Scalar* force = f.data();
    const Scalar *sx = shareX.data(), *sy = shareY.data(), *sz = shareZ.data();
    forChunks(pool, n, [=](int begin, int end) {
        for (Index p = begin; p < end; ++p) {
            Scalar fx = force[3 * p], fy = force[3 * p + 1], fz = force[3 * p + 2];
            for (Index k = start[p]; k < start[p + 1]; ++k) {
                const Index t = of[k];
                fx += sx[t], fy += sy[t], fz += sz[t];
            }
            force[3 * p] = fx, force[3 * p + 1] = fy, force[3 * p + 2] = fz;
            if (jacobian)
                for (Index k = start[p]; k < start[p + 1]; ++k) jacobian[p] += block[of[k]];
        }
    });
}

namespace {

// The eigen-decomposition's answer for the cases the closed form leaves (a repeated eigenvalue).
Mat3 projectByEigenvectors(const Mat3& sym) {
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(sym);
    const Vec3 lambda = eig.eigenvalues().cwiseMax(Scalar(0));
    return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

// A unit vector m x = 0 for m = a - lambda I of rank 2: the longest cross product of two rows;
// false when every one is too short to trust (rank below 2: a repeated eigenvalue).
bool nullVector(const Mat3& a, Scalar lambda, Vec3& out) {
    const Scalar m00 = a(0, 0) - lambda, m11 = a(1, 1) - lambda, m22 = a(2, 2) - lambda;
    const Scalar m01 = a(0, 1), m02 = a(0, 2), m12 = a(1, 2);
    // The rows' cross products (the matrix is symmetric): r0 x r1, r0 x r2, r1 x r2.
    const Vec3 c[3] = {Vec3(m01 * m12 - m02 * m11, m02 * m01 - m00 * m12, m00 * m11 - m01 * m01),
                       Vec3(m01 * m22 - m02 * m12, m02 * m02 - m00 * m22, m00 * m12 - m01 * m02),
                       Vec3(m11 * m22 - m12 * m12, m12 * m02 - m01 * m22, m01 * m12 - m11 * m02)};
    Scalar length[3] = {c[0].squaredNorm(), c[1].squaredNorm(), c[2].squaredNorm()};
    const int best = length[0] >= length[1] ? (length[0] >= length[2] ? 0 : 2) : (length[1] >= length[2] ? 1 : 2);
    const Scalar scale = m00 * m00 + m11 * m11 + m22 * m22 + 2 * (m01 * m01 + m02 * m02 + m12 * m12);
    if (!(length[best] > Scalar(1e-18) * scale * scale)) return false;
    out = c[best] / std::sqrt(length[best]);
    return true;
}

}  // namespace

// The eigenvalues of a symmetric 3x3, largest first, by the trigonometric solution of its
// characteristic polynomial (one arc cosine and two cosines).
Vec3 eigenvaluesOf(const Mat3& a) {
    const Scalar q = a.trace() / 3;
    const Scalar off = a(0, 1) * a(0, 1) + a(0, 2) * a(0, 2) + a(1, 2) * a(1, 2);
    const Scalar p2 = ((a(0, 0) - q) * (a(0, 0) - q) + (a(1, 1) - q) * (a(1, 1) - q) + (a(2, 2) - q) * (a(2, 2) - q) +
                       2 * off) / 6;
    if (!(p2 > 0)) return Vec3::Constant(q);
    const Scalar p = std::sqrt(p2);
    const Scalar r = std::clamp((a - q * Mat3::Identity()).determinant() / (2 * p * p2), Scalar(-1), Scalar(1));
    const Scalar phi = std::acos(r) / 3, third = Scalar(2.0943951023931954923);  // 2 pi / 3
    const Scalar l1 = q + 2 * p * std::cos(phi), l3 = q + 2 * p * std::cos(phi + third);
    return Vec3(l1, 3 * q - l1 - l3, l3);
}

Scalar smallestEigenvalue(const Mat3& a) { return eigenvaluesOf(a)(2); }

// The symmetric part of -dfdv with its negative eigenvalues set to zero, in closed form: the
// eigenvalues (above); none negative, the matrix itself; one negative, the matrix less that
// eigenvalue's part; two, the largest eigenvalue's part alone.
Mat3 dampingBlock(const Mat3& dfdv) {
    const Mat3 sym = Scalar(-0.5) * (dfdv + dfdv.transpose());
    const Vec3 l = eigenvaluesOf(sym);
    if (l(2) >= 0) return sym;
    Vec3 v;
    if (l(1) >= 0) {
        if (nullVector(sym, l(2), v)) return sym - l(2) * v * v.transpose();
    } else if (l(0) > 0) {
        if (nullVector(sym, l(0), v)) return l(0) * v * v.transpose();
    } else {
        return Mat3::Zero();
    }
    return projectByEigenvectors(sym);
}

void airDamping(const std::vector<Mat3>& velocityJacobian, std::vector<Mat3>& damping, ThreadPool* pool) {
    damping.resize(velocityJacobian.size());
    forChunks(pool, Index(velocityJacobian.size()), [&](int begin, int end) {
        for (int i = begin; i < end; ++i) damping[i] = dampingBlock(velocityJacobian[i]);
    });
}

}  // namespace cloth
