// Solvers against dense linear algebra written here: Wang's Chebyshev recurrence run on the dense
// matrix with dense 3x3 block Jacobi; the full 3n x 3n backward Euler system (springs, eq. 17,
// drag, damping, external force) built here and solved densely with the pins eliminated.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "physics_support.h"
#include <Eigen/Cholesky>

#include "cloth/paper_step.h"
#include "cloth/presets.h"

using namespace cloth;
using namespace cloth::test;

namespace {

// ---------------------------------------------------------------------------------------------
// Dense linear algebra for the solver tests

// The block diagonal (3x3 blocks) of a dense matrix, inverted block by block.
Eigen::MatrixXd blockDiagonalInverse(const Eigen::MatrixXd& W) {
    Eigen::MatrixXd inv = Eigen::MatrixXd::Zero(W.rows(), W.cols());
    for (Eigen::Index b = 0; b < W.rows(); b += 3) inv.block(b, b, 3, 3) = Mat3(W.block(b, b, 3, 3)).inverse();
    return inv;
}

Eigen::MatrixXd blockDiagonal(const Eigen::MatrixXd& W) {
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(W.rows(), W.cols());
    for (Eigen::Index b = 0; b < W.rows(); b += 3) d.block(b, b, 3, 3) = W.block(b, b, 3, 3);
    return d;
}

// Adds the 3x3 block B at block position (i, j).
void addBlock(Eigen::MatrixXd& A, Index i, Index j, const Mat3& B) { A.block<3, 3>(3 * i, 3 * j) += B; }

}  // namespace

// =============================================================================================
// 4. Chebyshev

TEST(PhysicsChebyshev, IteratesEqualTheRecurrenceOnTheDenseSystem) {
    const Cloth c = deformedGrid(6, 5, {3e3, 3e3, 300}, 0.05, 0.5, 21);
    const std::vector<Pin> pins = movingPins(c, 22);
    const Points external = randomPoints(c.model.particleCount(), 0.02, 23);
    Environment env;
    env.drag = 0.3;
    const StepInput input = stepInput(1.0 / 60, pins, &external);
    LinearSystem sys;
    buildSystem({c.model, env, c.state, input, true}, sys);
    const Eigen::MatrixXd W(assembleMatrix(c.model, sys));
    const Eigen::VectorXd b = flat(sys.rhs);  // pinned rows of W are identity, b their dv
    const Eigen::MatrixXd Dinv = blockDiagonalInverse(W), offDiagonal = W - blockDiagonal(W);
    auto jacobi = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return Dinv * (b - offDiagonal * x); };

    const Scalar rho = 0.9;
    for (int K : {1, 2, 5}) {
        // Wang 2015: x(k+1) = w(k+1) (J(x(k)) - x(k-1)) + x(k-1), w1 = 1, w2 = 2 / (2 - rho^2),
        // w(k+1) = 4 / (4 - rho^2 w(k)), from x(0) = x(-1) = W_ii^-1 b_i.
        Eigen::VectorXd previous = Dinv * b, current = previous;
        Scalar w = 1;
        for (int k = 1; k <= K; ++k) {
            w = k == 1 ? 1 : k == 2 ? 2 / (2 - rho * rho) : 4 / (4 - rho * rho * w);
            Eigen::VectorXd next = w * (jacobi(current) - previous) + previous;
            previous = current;
            current = next;
        }
        auto solver = solverFor("chebyshev:iterations=" + std::to_string(K) + ",rho=0.9");
        ASSERT_TRUE(solver);
        State state = c.state;
        ASSERT_EQ(solver->step(c.model, env, state, input).status, StepStatus::Ok);
        EXPECT_LE(relativeError(flat(solver->lastDv()), current), 1e-10)
            << "chebyshev:iterations=" << K << ",rho=0.9: lastDv() differs from the dense recurrence";
    }
}


// =============================================================================================
// 5. Pins and drag: the full backward Euler system

TEST(PhysicsPins, ExactStepSolvesTheFullBackwardEulerSystemWithPinsDragAndForces) {
    const Cloth c = deformedGrid(5, 4, {1e3, 1e3, 100}, 0.15, 1.0, 31);
    const Model& model = c.model;
    const State& s = c.state;
    const int n = model.particleCount(), N = 3 * n;
    const std::vector<Pin> pins = movingPins(c, 32);
    const Points external = randomPoints(n, 0.05, 33);
    std::vector<Mat3> damping(n);  // symmetric positive semi-definite C_i
    for (Index i = 0; i < n; ++i) {
        const Mat3 B = randomPoints(3, 0.1, 100 + i);
        damping[i] = B * B.transpose();
    }
    Environment env;
    env.drag = 0.8;
    StepInput input = stepInput(1.0 / 120, pins, &external);
    input.damping = &damping;
    const Scalar h = input.h;

    // f(x, v) and its derivatives K = df/dx, D = df/dv, all written out here.
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N, N), K = M, D = M;
    Eigen::VectorXd f(N);
    for (Index i = 0; i < n; ++i) {
        const Scalar m = model.masses()[i];
        addBlock(M, i, i, m * Mat3::Identity());
        addBlock(D, i, i, -env.drag * m * Mat3::Identity() - damping[i]);  // C_i = -df_i/dv_i
        f.segment<3>(3 * i) = m * env.gravity - env.drag * m * s.v.col(i) + external.col(i);
    }
    int stretched = 0, compressed = 0;
    for (const Spring& sp : model.springs()) {
        const Vec3 d = s.x.col(sp.j) - s.x.col(sp.i);
        const Scalar L = d.norm();
        const Vec3 u = d / L;
        f.segment<3>(3 * sp.i) += sp.k * (L - sp.rest) * u;  // eq. 15
        f.segment<3>(3 * sp.j) -= sp.k * (L - sp.rest) * u;
        const Scalar r = std::min(sp.rest / L, Scalar(1));  // eq. 17: l0 := L under compression
        const Mat3 J = sp.k * ((1 - r) * Mat3::Identity() + r * u * u.transpose());  // eq. 16
        addBlock(K, sp.i, sp.j, J);
        addBlock(K, sp.j, sp.i, J);
        addBlock(K, sp.i, sp.i, -J);
        addBlock(K, sp.j, sp.j, -J);
        (L > sp.rest ? stretched : compressed) += 1;
    }
    ASSERT_GT(stretched, 5);
    ASSERT_GT(compressed, 5);  // eq. 17 is exercised

    // Linearized backward Euler: (M - h D - h^2 K) dv = h (f + h K v).
    const Eigen::MatrixXd A = M - h * D - h * h * K;
    const Eigen::VectorXd b = h * (f + h * K * flat(s.v));

    // Pinned dv lands the particle on its target: dv_p = (x_target - x_p) / h - v_p. Eliminate
    // those unknowns: A_FF dv_F = b_F - A_FP dv_P.
    std::vector<bool> isPinned(n, false);
    Eigen::VectorXd dv = Eigen::VectorXd::Zero(N);
    for (const Pin& p : pins) {
        isPinned[p.particle] = true;
        dv.segment<3>(3 * p.particle) = (p.x - s.x.col(p.particle)) / h - s.v.col(p.particle);
    }
    std::vector<Eigen::Index> freeRows, pinRows;
    for (Index i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) (isPinned[i] ? pinRows : freeRows).push_back(3 * i + a);
    const Eigen::MatrixXd Aff = A(freeRows, freeRows), Afp = A(freeRows, pinRows);
    const Eigen::VectorXd dvFree = Aff.ldlt().solve(b(freeRows) - Afp * dv(pinRows));
    ASSERT_LE((Aff * dvFree - (b(freeRows) - Afp * dv(pinRows))).norm(), 1e-12 * b.norm());
    dv(freeRows) = dvFree;

    auto solver = solverFor("exact");
    ASSERT_TRUE(solver);
    State state = s;
    ASSERT_EQ(solver->step(model, env, state, input).status, StepStatus::Ok);
    const Points dense = Eigen::Map<const Points>(dv.data(), 3, n);
    Index worst = 0;
    (solver->lastDv() - dense).colwise().norm().maxCoeff(&worst);
    EXPECT_LE(relativeError(flat(solver->lastDv()), dv), 1e-8)
        << "dv of 'exact' differs from the dense backward Euler solve; worst particle " << worst
        << (isPinned[worst] ? " (pinned)" : " (free)") << ": " << solver->lastDv().col(worst).transpose()
        << " vs " << dense.col(worst).transpose();

    // The state after the step: v += dv, x += h v for free particles; pins on their targets.
    for (Index i = 0; i < n; ++i) {
        if (isPinned[i]) continue;
        const Vec3 v = s.v.col(i) + dv.segment<3>(3 * i);
        EXPECT_LE((state.v.col(i) - v).norm(), 1e-8 * v.norm()) << "particle " << i;
        EXPECT_LE((state.x.col(i) - (s.x.col(i) + h * v)).norm(), 1e-8 * h * v.norm()) << "particle " << i;
    }
    for (const Pin& p : pins) {
        EXPECT_EQ(state.x.col(p.particle), p.x) << "pinned particle " << p.particle;
        EXPECT_EQ(state.v.col(p.particle), p.v) << "pinned particle " << p.particle;
    }
}
