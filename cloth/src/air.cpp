#include "cloth/air.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "simd.h"

namespace cloth {

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
    if (velocityJacobian) velocityJacobian->assign(n, Mat3::Zero());
    Mat3* jacobian = velocityJacobian ? velocityJacobian->data() : nullptr;
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
