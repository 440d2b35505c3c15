// The air force's whole derivative (air.h, AirJacobian). With a = rho/4, alpha = c_d - c_f + c_l,
// s = |w|, q = w . N, L = |N|, the force of air.h is
//   F = a (beta N + gamma w),   beta = alpha s q / L,   gamma = c_f s L - c_l q^2 / (L s)
// so that
//   dF/dw = a (N grad_w(beta)^T + gamma I + w grad_w(gamma)^T)
//   dF/dN = a (beta I + N grad_N(beta)^T + w grad_N(gamma)^T)
// with grad_w s = w / s, grad_w q = N, grad_N q = w, grad_N L = N / L. Each corner takes F / 3,
// w = wind - (v_a + v_b + v_c) / 3 and dN = dx_ab x e2 + e1 x dx_ac (e1 = b - a, e2 = c - a).

#include "cloth/air.h"

#include <type_traits>

#include "cloth/parallel_for.h"
#include "eigen_order.h"

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

// The product's pass over the triangles: raw views of AirJacobian's arrays.
struct TrianglePass {
    const Index* corners;  // 3 per triangle
    const double* in;
    Scalar positionScale, velocityScale;
    const Scalar* dFdw[9];
    const Scalar* dFdN[9];
    const Scalar* e1[3];
    const Scalar* e2[3];
    Scalar* share;  // 3 per triangle
};

// Coordinate c of corner k of triangles t.. (one per lane of V).
template <class V>
CLOTH_INLINE inline V cornerOf(const TrianglePass& p, int k, int c, int t) {
    if constexpr (std::is_same_v<V, double>) {
        return p.in[3 * std::size_t(p.corners[3 * std::size_t(t) + k]) + c];
    } else {
        V v;
        for (int l = 0; l < kLanes<double>; ++l) v[l] = p.in[3 * std::size_t(p.corners[3 * std::size_t(t + l) + k]) + c];
        return v;
    }
}

// Triangles t.. (a lane each): share = (-(vs / 3) dF/dw (a + b + c) + ps dF/dN (da x e2 + e1 x dc)) / 3,
// each operation in the order of its Eigen form (eigen_order.h: a pack's lanes and the scalar tail
// give its bits).
template <class V>
CLOTH_INLINE inline void triangleShare(const TrianglePass& p, int t) {
    V x[3][3];  // corner, coordinate
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) x[k][c] = cornerOf<V>(p, k, c, t);
    V dF[3] = {};
    if (p.velocityScale != 0) {
        const V sum[3] = {x[0][0] + x[1][0] + x[2][0], x[0][1] + x[1][1] + x[2][1], x[0][2] + x[1][2] + x[2][2]};
        const Scalar f = p.velocityScale / 3;
        for (int r = 0; r < 3; ++r) dF[r] = dF[r] - scaledMat3Row<V>(f, p.dFdw, r, sum, std::size_t(t));
    }
    if (p.positionScale != 0) {
        V da[3], dc[3], e1[3], e2[3];
        for (int c = 0; c < 3; ++c) {
            da[c] = x[1][c] - x[0][c], dc[c] = x[2][c] - x[0][c];
            e1[c] = load<V>(p.e1[c] + t), e2[c] = load<V>(p.e2[c] + t);
        }
        V dN[3];
        for (int c = 0; c < 3; ++c) {
            const int i = (c + 1) % 3, j = (c + 2) % 3;
            dN[c] = (da[i] * e2[j] - da[j] * e2[i]) + (e1[i] * dc[j] - e1[j] * dc[i]);
        }
        for (int r = 0; r < 3; ++r) dF[r] = dF[r] + scaledMat3Row<V>(p.positionScale, p.dFdN, r, dN, std::size_t(t));
    }
    // share: 3 per triangle, so that a corner's gather reads them together
    for (int r = 0; r < 3; ++r) storeStrided<V>(p.share, std::size_t(t), 3, r, dF[r] / 3);
}

CLOTH_SIMD_CLONES void triangleShares(const TrianglePass& p, int begin, int end) {
    int t = begin;
    for (; t + kLanes<double> <= end; t += kLanes<double>) triangleShare<Pack<double>>(p, t);
    for (; t < end; ++t) triangleShare<double>(p, t);
}

}  // namespace

void AirJacobian::compute(const Model& model, const State& state, const AirParams& air, ThreadPool* pool) {
    const auto& triangles = model.triangles();
    const std::size_t count = triangles.size();
    for (auto* arrays : {&dFdw_, &dFdN_})
        for (std::vector<Scalar>& entry : *arrays) entry.resize(count);
    for (auto* arrays : {&e1_, &e2_})
        for (std::vector<Scalar>& coordinate : *arrays) coordinate.resize(count);
    share_.resize(3 * count);
    forChunks(pool, int(count), [&](int begin, int end) {
        for (int t = begin; t < end; ++t) {
            const Triangle& tri = triangles[t];
            const Vec3 a = state.x.col(tri[0]), e1 = state.x.col(tri[1]) - a, e2 = state.x.col(tri[2]) - a;
            const Vec3 w = air.wind - (state.v.col(tri[0]) + state.v.col(tri[1]) + state.v.col(tri[2])) / 3;
            const TriangleDerivative d = derivative(e1.cross(e2), w, air);
            for (int r = 0; r < 3; ++r) {
                e1_[r][t] = e1[r], e2_[r][t] = e2[r];
                for (int c = 0; c < 3; ++c) dFdw_[3 * r + c][t] = d.dFdw(r, c), dFdN_[3 * r + c][t] = d.dFdN(r, c);
            }
        }
    });
}

void AirJacobian::triangleParts(const Model& model, const double* in, Scalar positionScale, Scalar velocityScale,
                                ThreadPool* pool) const {
    TrianglePass pass{&model.triangles()[0][0], in, positionScale, velocityScale, {}, {}, {}, {}, share_.data()};
    for (int k = 0; k < 9; ++k) pass.dFdw[k] = dFdw_[k].data(), pass.dFdN[k] = dFdN_[k].data();
    for (int k = 0; k < 3; ++k) pass.e1[k] = e1_[k].data(), pass.e2[k] = e2_[k].data();
    forChunks(pool, int(model.triangles().size()), [&](int begin, int end) { triangleShares(pass, begin, end); });
}

void AirJacobian::addParts(const Model& model, int begin, int end, double* out) const {
    const Index* start = model.triStart().data();
    const Index* of = model.triOf().data();
    for (Index p = begin; p < end; ++p)
        for (Index k = start[p]; k < start[p + 1]; ++k)
            for (int c = 0; c < 3; ++c) out[3 * p + c] += share_[3 * std::size_t(of[k]) + c];
}

void AirJacobian::apply(const Model& model, const double* in, Scalar positionScale, Scalar velocityScale,
                        double* out) const {
    triangleParts(model, in, positionScale, velocityScale);
    addParts(model, 0, int(model.particleCount()), out);
}

void AirJacobian::velocityDiagonal(const Model& model, std::vector<Mat3>& out, ThreadPool* pool) const {
    const std::size_t count = model.triangles().size();
    ninth_.resize(9 * count);  // each triangle's dF/dw / 9, its 9 entries together
    forChunks(pool, int(count), [&](int begin, int end) {
        for (int t = begin; t < end; ++t)
            for (int e = 0; e < 9; ++e) ninth_[9 * std::size_t(t) + e] = dFdw_[e][t] / 9;
    });
    out.assign(model.particleCount(), Mat3::Zero());
    const Index* start = model.triStart().data();
    const Index* of = model.triOf().data();
    forChunks(pool, int(model.particleCount()), [&](int begin, int end) {
        for (Index p = begin; p < end; ++p)
            for (Index k = start[p]; k < start[p + 1]; ++k)
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) out[p](r, c) -= ninth_[9 * std::size_t(of[k]) + 3 * r + c];
    });
}

}  // namespace cloth
