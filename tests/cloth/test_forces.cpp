// Spring kernels against independent computations: finite differences of the energy and of the
// force, and conservation of momentum and angular momentum.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "cloth/forces.h"
#include "cloth/system.h"

using namespace cloth;

namespace {

const Scalar kK = 250.0, kRest = 0.8;

Vec3 fdGradientOfEnergy(const Vec3& xi, const Vec3& xj) {
    const Scalar eps = 1e-6;
    Vec3 g;
    for (int a = 0; a < 3; ++a) {
        Vec3 p = xi, m = xi;
        p[a] += eps;
        m[a] -= eps;
        g[a] = (springEnergy(p, xj, kK, kRest) - springEnergy(m, xj, kK, kRest)) / (2 * eps);
    }
    return g;
}

// Central differences of f_i with respect to x_j: the true Jacobian block.
Mat3 fdJacobian(const Vec3& xi, const Vec3& xj) {
    const Scalar eps = 1e-6;
    Mat3 J;
    for (int a = 0; a < 3; ++a) {
        Vec3 p = xj, m = xj;
        p[a] += eps;
        m[a] -= eps;
        J.col(a) = (springForce(xi, p, kK, kRest) - springForce(xi, m, kK, kRest)) / (2 * eps);
    }
    return J;
}

}  // namespace

TEST(SpringForce, IsMinusGradientOfEnergy) {
    const Vec3 xi(0.1, -0.2, 0.3), xj(0.9, 0.4, -0.1);  // length 1.08 > rest: tension
    const Vec3 f = springForce(xi, xj, kK, kRest);
    EXPECT_GT((xj - xi).norm(), kRest);
    EXPECT_LT((f + fdGradientOfEnergy(xi, xj)).norm(), 1e-6 * f.norm());
}

TEST(SpringJacobian, MatchesFiniteDifferencesUnderTension) {
    const Vec3 xi(0.1, -0.2, 0.3), xj(0.9, 0.4, -0.1);
    const Mat3 fd = fdJacobian(xi, xj);
    for (bool rule : {true, false}) {
        const Mat3 J = springJacobian(xi, xj, kK, kRest, rule);
        EXPECT_LT((J - fd).norm(), 1e-5 * fd.norm()) << "compression rule " << rule;
    }
}

TEST(SpringJacobian, UnderCompressionRuleGivesKuuTAndIsPsd) {
    const Vec3 xi(0, 0, 0), xj(0.3, 0.2, 0.1);  // length 0.37 < rest 0.8
    const Vec3 u = (xj - xi).normalized();
    const Mat3 J = springJacobian(xi, xj, kK, kRest, true);
    EXPECT_LT((J - kK * u * u.transpose()).norm(), 1e-12 * kK);
    Eigen::SelfAdjointEigenSolver<Mat3> eig(J);
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * kK);
    // Without the rule the block is the true Jacobian, which is indefinite under compression.
    const Mat3 raw = springJacobian(xi, xj, kK, kRest, false);
    EXPECT_LT((raw - fdJacobian(xi, xj)).norm(), 1e-5 * raw.norm());
    Eigen::SelfAdjointEigenSolver<Mat3> eigRaw(raw);
    EXPECT_LT(eigRaw.eigenvalues().minCoeff(), 0);
}

TEST(InternalForces, SumToZeroWithNoNetTorque) {
    GridDesc g;
    g.nx = 7;
    g.ny = 5;
    const Model model = Model::fromGrid(g);
    State state = State::atRest(model);
    std::mt19937 rng(7);
    std::uniform_real_distribution<Scalar> jitter(-0.05, 0.05);
    for (Index i = 0; i < model.particleCount(); ++i)
        for (int a = 0; a < 3; ++a) state.x(a, i) += jitter(rng);
    Environment env;
    env.gravity.setZero();
    Points f;
    computeForces(model, env, state, nullptr, f);
    Vec3 total = Vec3::Zero(), torque = Vec3::Zero();
    Scalar scale = 0;
    for (Index i = 0; i < model.particleCount(); ++i) {
        total += f.col(i);
        torque += state.x.col(i).cross(f.col(i));
        scale += f.col(i).norm();
    }
    ASSERT_GT(scale, 1.0);  // the jitter really deformed the cloth
    EXPECT_LT(total.norm(), 1e-12 * scale);
    EXPECT_LT(torque.norm(), 1e-12 * scale);
}
