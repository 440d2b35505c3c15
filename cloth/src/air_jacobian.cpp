// The air force's whole derivative (air.h, AirJacobian). With a = rho/4, alpha = c_d - c_f + c_l,
// s = |w|, q = w . N, L = |N|, the force of air.h is
//   F = a (beta N + gamma w),   beta = alpha s q / L,   gamma = c_f s L - c_l q^2 / (L s)
// so that
//   dF/dw = a (N grad_w(beta)^T + gamma I + w grad_w(gamma)^T)
//   dF/dN = a (beta I + N grad_N(beta)^T + w grad_N(gamma)^T)
// with grad_w s = w / s, grad_w q = N, grad_N q = w, grad_N L = N / L. Each corner takes F / 3,
// w = wind - (v_a + v_b + v_c) / 3 and dN = dx_ab x e2 + e1 x dx_ac (e1 = b - a, e2 = c - a).

#include "cloth/air.h"

namespace cloth {

namespace {

struct TriangleDerivative {
    Mat3 dFdw = Mat3::Zero(), dFdN = Mat3::Zero();
};

TriangleDerivative derivative(const Vec3& N, const Vec3& w, const AirParams& air) {
    TriangleDerivative d;
    const Scalar L = N.norm(), s = w.norm();
    if (L < 1e-14 || s < 1e-9) return d;  // addAirForces' cases with no force
    const Scalar a = Scalar(0.25) * air.density;
    const Scalar cf = air.frictionCoefficient, cl = air.liftCoefficient;
    const Scalar alpha = air.dragCoefficient - cf + cl;
    const Scalar q = w.dot(N);
    const Scalar beta = alpha * s * q / L, gamma = cf * s * L - cl * q * q / (L * s);
    const Vec3 betaW = alpha * (q * w / s + s * N) / L;
    const Vec3 betaN = alpha * s * (w / L - q * N / (L * L * L));
    const Vec3 gammaW = cf * L * w / s - cl * (2 * q * N / (L * s) - q * q * w / (L * s * s * s));
    const Vec3 gammaN = cf * s * N / L - cl * (2 * q * w / (L * s) - q * q * N / (L * L * L * s));
    d.dFdw = a * (N * betaW.transpose() + gamma * Mat3::Identity() + w * gammaW.transpose());
    d.dFdN = a * (beta * Mat3::Identity() + N * betaN.transpose() + w * gammaN.transpose());
    return d;
}

}  // namespace

void AirJacobian::compute(const Model& model, const State& state, const AirParams& air) {
    const auto& triangles = model.triangles();
    dFdw_.resize(triangles.size()), dFdN_.resize(triangles.size());
    e1_.resize(triangles.size()), e2_.resize(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Triangle& tri = triangles[t];
        const Vec3 a = state.x.col(tri[0]);
        e1_[t] = state.x.col(tri[1]) - a;
        e2_[t] = state.x.col(tri[2]) - a;
        const Vec3 w = air.wind - (state.v.col(tri[0]) + state.v.col(tri[1]) + state.v.col(tri[2])) / 3;
        const TriangleDerivative d = derivative(e1_[t].cross(e2_[t]), w, air);
        dFdw_[t] = d.dFdw;
        dFdN_[t] = d.dFdN;
    }
}

void AirJacobian::apply(const Model& model, const double* in, Scalar positionScale, Scalar velocityScale,
                        double* out) const {
    const auto& triangles = model.triangles();
    share_.resize(triangles.size());
    auto at = [](const double* p, Index i) { return Vec3(p[3 * i], p[3 * i + 1], p[3 * i + 2]); };
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Triangle& tri = triangles[t];
        const Vec3 a = at(in, tri[0]), b = at(in, tri[1]), c = at(in, tri[2]);
        Vec3 dF = Vec3::Zero();
        if (velocityScale != 0) dF -= (velocityScale / 3) * (dFdw_[t] * (a + b + c));
        if (positionScale != 0) dF += positionScale * (dFdN_[t] * ((b - a).cross(e2_[t]) + e1_[t].cross(c - a)));
        share_[t] = dF / 3;
    }
    const Index* start = model.triStart().data();
    const Index* of = model.triOf().data();
    for (Index p = 0; p < model.particleCount(); ++p)
        for (Index k = start[p]; k < start[p + 1]; ++k)
            for (int c = 0; c < 3; ++c) out[3 * p + c] += share_[of[k]][c];
}

void AirJacobian::velocityDiagonal(const Model& model, std::vector<Mat3>& out) const {
    out.assign(model.particleCount(), Mat3::Zero());
    const Index* start = model.triStart().data();
    const Index* of = model.triOf().data();
    for (Index p = 0; p < model.particleCount(); ++p)
        for (Index k = start[p]; k < start[p + 1]; ++k) out[p] -= dFdw_[of[k]] / 9;
}

}  // namespace cloth
