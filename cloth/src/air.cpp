#include "cloth/air.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "simd.h"

namespace cloth {

namespace {

struct ShareArgs {
    const Triangle* triangles;
    const Scalar *x, *v;  // 3 x n, column-major
    Scalar windX, windY, windZ, scale, normal, friction, lift;
    Scalar *sx, *sy, *sz;  // per triangle
};

// Without the velocity Jacobian: every triangle's share of its force, the arithmetic of
// triangleShare() below written out per coordinate. Per tile of triangles, the corners' edges and
// the relative air are gathered into arrays, then the rest runs one triangle a SIMD lane, with a
// select in place of the early return. The same bits as triangleShare().
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

}  // namespace

void addAirForces(const Model& model, const State& state, const AirParams& air, Points& f,
                  std::vector<Mat3>* velocityJacobian, ThreadPool* pool) {
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
    // One triangle's share of its force, and of -dF/dv when block is non-null; false (and zeros)
    // for a degenerate triangle or no relative air.
    auto triangleShare = [&](Index k, Vec3& share, Mat3* block) CLOTH_INLINE -> bool {
        const Triangle& t = triangles[k];
        const Vec3 a = state.x.col(t[0]), b = state.x.col(t[1]), c = state.x.col(t[2]);
        const Vec3 N = (b - a).cross(c - a);
        const Vec3 w = wind - (state.v.col(t[0]) + state.v.col(t[1]) + state.v.col(t[2])) / 3;
        const Scalar twiceArea = N.norm(), s = w.norm(), q = w.dot(N);
        if (twiceArea < 1e-14 || s < 1e-9) {
            share.setZero();
            if (block) block->setZero();
            return false;
        }
        const Scalar inv = 1 / (twiceArea * s);
        share = (quarterRho / 3) * ((normal * s * s * q * inv) * N +
                                    (friction * s * twiceArea - lift * q * q * inv) * w);
        if (!block) return true;
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
        *block = -(dDrag + dFriction + dLift) / 9;
        return true;
    };
    if (!velocityJacobian) {
        // Every triangle's share (vectorized), then each particle's sum over its triangles in
        // increasing order: the order in which the loop below adds them, so the same bits.
        static thread_local std::vector<Scalar> shareX, shareY, shareZ;
        shareX.resize(count), shareY.resize(count), shareZ.resize(count);
        const ShareArgs args{triangles.data(), state.x.data(), state.v.data(), wind.x(), wind.y(), wind.z(),
                             quarterRho / 3, normal, friction, lift, shareX.data(), shareY.data(), shareZ.data()};
        const Index* start = model.triStart().data();
        const Index* of = model.triOf().data();
        Scalar* force = f.data();
        // Pointers, not the thread_local vectors: a worker thread naming them would get its own.
        const Scalar *shareXs = shareX.data(), *shareYs = shareY.data(), *shareZs = shareZ.data();
        auto sum = [=](int begin, int end) {
            for (Index p = begin; p < end; ++p) {
                Scalar fx = force[3 * p], fy = force[3 * p + 1], fz = force[3 * p + 2];
                for (Index k = start[p]; k < start[p + 1]; ++k) {
                    const Index t = of[k];
                    fx += shareXs[t], fy += shareYs[t], fz += shareZs[t];
                }
                force[3 * p] = fx, force[3 * p + 1] = fy, force[3 * p + 2] = fz;
            }
        };
        if (!pool || pool->threads() < 2) {
            triangleShares(args, 0, count);
            sum(0, n);
        } else {
            pool->run(count, [&](int begin, int end) { triangleShares(args, begin, end); });
            pool->run(n, sum);
        }
        return;
    }
    velocityJacobian->assign(n, Mat3::Zero());
    Mat3* jacobian = velocityJacobian->data();
    if (!pool || pool->threads() < 2) {  // one loop, each share added to its corners
        for (Index k = 0; k < count; ++k) {
            Vec3 share;
            Mat3 block;
            if (!triangleShare(k, share, jacobian ? &block : nullptr)) continue;
            const Triangle& t = triangles[k];
            f.col(t[0]) += share;
            f.col(t[1]) += share;
            f.col(t[2]) += share;
            if (jacobian)
                for (const Index p : t) jacobian[p] += block;
        }
        return;
    }
    // Threads: first every triangle's share, then each particle's sum over its triangles in
    // increasing order, the order of the loop above (the same bits); no two threads write one place.
    static thread_local std::vector<Vec3> shares;
    static thread_local std::vector<Mat3> blocks;
    shares.resize(count);
    if (jacobian) blocks.resize(count);
    Vec3* share = shares.data();
    Mat3* block = blocks.data();
    pool->run(count, [&](int begin, int end) {
        for (Index k = begin; k < end; ++k) triangleShare(k, share[k], jacobian ? &block[k] : nullptr);
    });
    const Index* start = model.triStart().data();
    const Index* of = model.triOf().data();
    pool->run(n, [&](int begin, int end) {
        for (Index p = begin; p < end; ++p) {
            Vec3 sum = f.col(p);
            for (Index k = start[p]; k < start[p + 1]; ++k) sum += share[of[k]];
            f.col(p) = sum;
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
