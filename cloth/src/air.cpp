#include "cloth/air.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace cloth {

void addAirForces(const Model& model, const State& state, const AirParams& air, Points& f,
                  std::vector<Mat3>* velocityJacobian) {
    // With N = (b - a) x (c - a) (|N| = 2 A, n = N / |N|) and q = w . N (wn = q / |N|), the three
    // terms of air.h add up to
    //   F = rho / 4 [(c_d - c_f + c_l) s q / |N| N + (c_f s |N| - c_l q^2 / (|N| s)) w]
    // with two square roots and one division, and no case on the side n faces: each term is even
    // in n (wn n, wn^2 and n n^T do not change when n flips).
    const Scalar quarterRho = Scalar(0.25) * air.density;
    const Scalar normal = air.dragCoefficient - air.frictionCoefficient + air.liftCoefficient;
    if (velocityJacobian) velocityJacobian->assign(model.particleCount(), Mat3::Zero());
    for (const Triangle& t : model.triangles()) {
        const Vec3 a = state.x.col(t[0]), b = state.x.col(t[1]), c = state.x.col(t[2]);
        const Vec3 N = (b - a).cross(c - a);
        const Vec3 w = air.wind - (state.v.col(t[0]) + state.v.col(t[1]) + state.v.col(t[2])) / 3;
        const Scalar twiceArea = N.norm(), s = w.norm(), q = w.dot(N);
        if (twiceArea < 1e-14 || s < 1e-9) continue;
        const Scalar inv = 1 / (twiceArea * s);
        const Vec3 share = (quarterRho / 3) * ((normal * s * s * q * inv) * N +
                                               (air.frictionCoefficient * s * twiceArea -
                                                air.liftCoefficient * q * q * inv) * w);
        f.col(t[0]) += share;
        f.col(t[1]) += share;
        f.col(t[2]) += share;
        if (!velocityJacobian) continue;
        // dF/dw with n fixed (n depends on x only): ds/dw = w^T / s, d(wn)/dw = n^T.
        const Scalar halfRho = 2 * quarterRho, area = Scalar(0.5) * twiceArea;
        const Scalar cd = halfRho * area * air.dragCoefficient;
        const Scalar cf = halfRho * area * air.frictionCoefficient;
        const Scalar cl = halfRho * area * air.liftCoefficient;
        const Vec3 n = N / twiceArea;
        const Scalar wn = w.dot(n);
        const Vec3 tangential = w - wn * n;
        const Mat3 I = Mat3::Identity(), nn = n * n.transpose(), nw = n * w.transpose();
        const Mat3 dDrag = cd * ((wn / s) * nw + s * nn);
        const Mat3 dFriction = cf * (tangential * w.transpose() / s + s * (I - nn));
        const Mat3 dLift = cl * (s * nn + (wn / s) * nw - (2 * wn / s) * nw.transpose() +
                                 (wn * wn / (s * s * s)) * (w * w.transpose()) - (wn * wn / s) * I);
        // f_i = F / 3 and dw/dv_i = -I / 3.
        const Mat3 block = -(dDrag + dFriction + dLift) / 9;
        for (const Index p : t) (*velocityJacobian)[p] += block;
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
