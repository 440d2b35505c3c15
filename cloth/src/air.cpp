#include "cloth/air.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>

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

// One triangle's share of -dF/dv (zero for a degenerate triangle or no relative air).
Mat3 triangleBlock(const State& state, const Triangle& t, const Vec3& wind, const AirParams& air,
                   Scalar quarterRho) {
    const Vec3 a = state.x.col(t[0]), b = state.x.col(t[1]), c = state.x.col(t[2]);
    const Vec3 N = (b - a).cross(c - a);
    const Vec3 w = wind - (state.v.col(t[0]) + state.v.col(t[1]) + state.v.col(t[2])) / 3;
    const Scalar twiceArea = N.norm(), s = w.norm();
    if (twiceArea < 1e-14 || s < 1e-9) return Mat3::Zero();
    // dF/dw with n fixed (n depends on x only): ds/dw = w^T / s, d(wn)/dw = n^T.
    const Scalar halfRho = 2 * quarterRho, area = Scalar(0.5) * twiceArea;
    const Scalar cd = halfRho * area * air.dragCoefficient;
    const Scalar cf = halfRho * area * air.frictionCoefficient;
    const Scalar cl = halfRho * area * air.liftCoefficient;
    const Vec3 nHat = N / twiceArea;
    const Scalar wn = w.dot(nHat);
    const Vec3 tangential = w - wn * nHat;
    const Mat3 I = Mat3::Identity(), nn = nHat * nHat.transpose(), nw = nHat * w.transpose();
    const Mat3 dDrag = cd * ((wn / s) * nw + s * nn);
    const Mat3 dFriction = cf * (tangential * w.transpose() / s + s * (I - nn));
    const Mat3 dLift = cl * (s * nn + (wn / s) * nw - (2 * wn / s) * nw.transpose() +
                             (wn * wn / (s * s * s)) * (w * w.transpose()) - (wn * wn / s) * I);
    // f_i = F / 3 and dw/dv_i = -I / 3.
    return -(dDrag + dFriction + dLift) / 9;
}

// A loop over [0, size) on the pool's threads when it has more than one, else here.
void runLoop(ThreadPool* pool, Index size, const std::function<void(int, int)>& body) {
    if (pool && pool->threads() > 1) pool->run(int(size), body);
    else body(0, int(size));
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
    runLoop(pool, count, [&](int begin, int end) { triangleShares(args, begin, end); });
    Mat3* jacobian = nullptr;
    const Mat3* block = nullptr;
    if (velocityJacobian) {
        velocityJacobian->assign(n, Mat3::Zero());
        jacobian = velocityJacobian->data();
        blocks.resize(count);
        Mat3* out = blocks.data();
        runLoop(pool, count, [&](int begin, int end) {
            for (Index k = begin; k < end; ++k) out[k] = triangleBlock(state, triangles[k], wind, air, quarterRho);
        });
        block = blocks.data();
    }
    const Index* start = model.triStart().data();
    const Index* of = model.triOf().data();
    Scalar* force = f.data();
    const Scalar *sx = shareX.data(), *sy = shareY.data(), *sz = shareZ.data();
    runLoop(pool, n, [=](int begin, int end) {
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

Mat3 dampingBlock(const Mat3& dfdv) {
    const Mat3 sym = Scalar(-0.5) * (dfdv + dfdv.transpose());
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(sym);
    const Vec3 lambda = eig.eigenvalues().cwiseMax(Scalar(0));
    return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

void airDamping(const std::vector<Mat3>& velocityJacobian, std::vector<Mat3>& damping) {
    damping.resize(velocityJacobian.size());
    for (std::size_t i = 0; i < velocityJacobian.size(); ++i) damping[i] = dampingBlock(velocityJacobian[i]);
}

}  // namespace cloth
