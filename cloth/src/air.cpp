#include "cloth/air.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace cloth {

void addAirForces(const Model& model, const State& state, const AirParams& air, Points& f,
                  std::vector<Mat3>* velocityJacobian) {
    const Scalar halfRho = Scalar(0.5) * air.density;
    if (velocityJacobian) velocityJacobian->assign(model.particleCount(), Mat3::Zero());
    for (const Triangle& t : model.triangles()) {
        const Vec3 a = state.x.col(t[0]), b = state.x.col(t[1]), c = state.x.col(t[2]);
        const Vec3 cross = (b - a).cross(c - a);
        const Scalar twiceArea = cross.norm();
        if (twiceArea < 1e-14) continue;
        const Scalar area = Scalar(0.5) * twiceArea;
        Vec3 n = cross / twiceArea;
        const Vec3 w = air.wind - (state.v.col(t[0]) + state.v.col(t[1]) + state.v.col(t[2])) / 3;
        const Scalar s = w.norm();
        if (s < 1e-9) continue;
        Scalar wn = w.dot(n);
        if (wn < 0) {  // orient n with the flow: the formulas below assume w . n >= 0
            n = -n;
            wn = -wn;
        }
        const Scalar cd = halfRho * area * air.dragCoefficient;
        const Scalar cf = halfRho * area * air.frictionCoefficient;
        const Scalar cl = halfRho * area * air.liftCoefficient;
        const Vec3 tangential = w - wn * n;
        Vec3 force = halfRho * area * s * (air.dragCoefficient * wn * n + air.frictionCoefficient * tangential);
        // Lift: perpendicular to w in the plane of w and n; cos(theta) sin(theta) |w|^2 with theta
        // the angle of attack. (Equal to c_l (wn s n - (wn^2 / s) w), the form differentiated below;
        // written this way so that recorded runs keep their bits.)
        const Vec3 liftDir = n - (wn / (s * s)) * w;
        const Scalar liftNorm = liftDir.norm();
        if (liftNorm > 1e-9) {
            const Scalar sinA = wn / s, cosA = tangential.norm() / s;
            force += halfRho * area * air.liftCoefficient * s * s * sinA * cosA * (liftDir / liftNorm);
        }
        const Vec3 share = force / 3;
        f.col(t[0]) += share;
        f.col(t[1]) += share;
        f.col(t[2]) += share;
        if (!velocityJacobian) continue;
        // dF/dw with n fixed (n depends on x only): ds/dw = w^T / s, d(wn)/dw = n^T.
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
