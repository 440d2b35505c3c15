#include "cloth/air.h"

#include <Eigen/Eigenvalues>
#include <cmath>

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
    const auto& triangles = model.triangles();
    const Index count = Index(triangles.size()), n = model.particleCount();
    // First each triangle's share of its force (and of -dF/dv), then each particle's sum over its
    // triangles in increasing order: the sums of a loop over the triangles, with the same bits,
    // and both loops split among threads without two writing one place.
    static thread_local std::vector<Vec3> shares;
    static thread_local std::vector<Mat3> blocks;
    shares.resize(count);
    if (velocityJacobian) blocks.resize(count);
    Vec3* share = shares.data();
    Mat3* block = blocks.data();
    auto perTriangle = [&](int begin, int end) {
        for (Index k = begin; k < end; ++k) {
            const Triangle& t = triangles[k];
            share[k].setZero();
            if (velocityJacobian) block[k].setZero();
            const Vec3 a = state.x.col(t[0]), b = state.x.col(t[1]), c = state.x.col(t[2]);
            const Vec3 N = (b - a).cross(c - a);
            const Vec3 w = air.wind - (state.v.col(t[0]) + state.v.col(t[1]) + state.v.col(t[2])) / 3;
            const Scalar twiceArea = N.norm(), s = w.norm(), q = w.dot(N);
            if (twiceArea < 1e-14 || s < 1e-9) continue;
            const Scalar inv = 1 / (twiceArea * s);
            share[k] = (quarterRho / 3) * ((normal * s * s * q * inv) * N +
                                           (air.frictionCoefficient * s * twiceArea - air.liftCoefficient * q * q * inv) * w);
            if (!velocityJacobian) continue;
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
            block[k] = -(dDrag + dFriction + dLift) / 9;
        }
    };
    if (velocityJacobian) velocityJacobian->assign(n, Mat3::Zero());
    Mat3* jacobian = velocityJacobian ? velocityJacobian->data() : nullptr;
    const Index* start = model.triStart().data();
    const Index* of = model.triOf().data();
    auto perParticle = [&](int begin, int end) {
        for (Index p = begin; p < end; ++p) {
            Vec3 sum = f.col(p);
            for (Index k = start[p]; k < start[p + 1]; ++k) sum += share[of[k]];
            f.col(p) = sum;
            if (jacobian)
                for (Index k = start[p]; k < start[p + 1]; ++k) jacobian[p] += block[of[k]];
        }
    };
    if (pool) {
        pool->run(count, perTriangle);
        pool->run(n, perParticle);
    } else {
        perTriangle(0, count);
        perParticle(0, n);
    }
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
