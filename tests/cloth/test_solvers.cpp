// Solvers against independent computations: a hand evaluation of eq. 14, the exact solve, the
// theory of Jacobi convergence, pins, stability. (Determinism: test_golden_hashes.cpp.)

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstring>
#include <random>

#include "cloth/exact_solve.h"
#include "cloth/paper_step.h"
#include "cloth/diagnostics.h"
#include "cloth/presets.h"
#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "solver_spec.h"

using namespace cloth;

namespace {

// A small grid with jittered positions and random velocities: some springs stretched, some
// compressed.
struct Scene {
    Model model;
    State state;
};
Scene deformedGrid(int nx, int ny, Scalar k, unsigned seed) {
    GridDesc g;
    g.nx = nx;
    g.ny = ny;
    g.width = 1.0;
    g.height = 1.0;
    g.stiffness = {k, k, k / 10};
    Scene s{Model::fromGrid(g), {}};
    s.state = State::atRest(s.model);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Scalar> jitter(-0.03, 0.03), vel(-0.5, 0.5);
    for (Index i = 0; i < s.model.particleCount(); ++i)
        for (int a = 0; a < 3; ++a) {
            s.state.x(a, i) += jitter(rng);
            s.state.v(a, i) = vel(rng);
        }
    return s;
}

}  // namespace

// Eq. 14 evaluated by hand on three particles, written out from the paper's formulas without the
// library's system builder.
TEST(KangCho, OneIterationEqualsHandEvaluationOfEq14) {
    Points rest(3, 3);
    rest << 0, 1, 0,  //
        0, 0, 1,      //
        0, 0, 0;
    const Model model = Model::fromMesh(rest, {{0, 1, 2}}, 0.3, {50, 50, 0});
    State state = State::atRest(model);
    state.x.col(1) = Vec3(1.2, 0.1, -0.05);  // stretched
    state.x.col(2) = Vec3(0.05, 0.7, 0.1);   // compressed
    state.v.col(0) = Vec3(0.1, -0.2, 0.3);
    state.v.col(1) = Vec3(-0.4, 0.0, 0.2);
    state.v.col(2) = Vec3(0.0, 0.5, -0.1);
    const Environment env;  // gravity, no drag
    const Scalar h = 0.02;

    // Hand evaluation.
    const auto& m = model.masses();
    Vec3 f[3];
    Mat3 W[3];
    for (int i = 0; i < 3; ++i) {
        f[i] = m[i] * env.gravity;
        W[i] = m[i] * Mat3::Identity();
    }
    Mat3 J[3][3];
    for (auto& row : J)
        for (auto& b : row) b.setZero();
    for (const Spring& s : model.springs()) {
        const Vec3 d = state.x.col(s.j) - state.x.col(s.i);
        const Scalar L = d.norm();
        const Vec3 u = d / L;
        f[s.i] += s.k * (L - s.rest) * u;  // eq. 15
        f[s.j] -= s.k * (L - s.rest) * u;
        const Scalar l0 = std::min(s.rest, L);  // eq. 17: l0 := L under compression
        const Mat3 Jij = s.k * ((1 - l0 / L) * Mat3::Identity() + (l0 / L) * u * u.transpose());
        J[s.i][s.j] = J[s.j][s.i] = Jij;  // eq. 16
        W[s.i] += h * h * Jij;            // eq. 12
        W[s.j] += h * h * Jij;
    }
    Vec3 dv0[3], dv1[3];
    for (int i = 0; i < 3; ++i) {
        Vec3 ft = f[i];  // eq. 7
        for (int j = 0; j < 3; ++j) ft += h * J[i][j] * (state.v.col(j) - state.v.col(i));
        dv0[i] = W[i].inverse() * (h * ft);
    }
    for (int i = 0; i < 3; ++i) {
        Vec3 sum = Vec3::Zero();
        for (int j = 0; j < 3; ++j) sum += J[i][j] * dv0[j];
        dv1[i] = dv0[i] + h * h * W[i].inverse() * sum;  // eq. 14
    }

    auto solver = solverOf("kangcho");
    StepInput input;
    input.h = h;
    const State before = state;
    ASSERT_EQ(solver->step(model, env, state, input).status, StepStatus::Ok);
    for (int i = 0; i < 3; ++i) {
        const Vec3 v = before.v.col(i) + dv1[i];
        EXPECT_LT((state.v.col(i) - v).norm(), 1e-12) << "particle " << i;
        EXPECT_LT((state.x.col(i) - (before.x.col(i) + h * v)).norm(), 1e-12) << "particle " << i;
    }
}

TEST(KangCho, JacobiApproachesExactSolveIterationByIteration) {
    Scene s = deformedGrid(9, 9, 1.0, 3);  // soft: h^2 k small against m
    const Environment env;
    StepInput input;
    input.h = 1.0 / 60;
    const std::vector<Pin> pins = pinColumn(s.model);
    input.pins = pins;
    LinearSystem sys;
    buildSystem({s.model, env, s.state, input, true}, sys);
    Points exact;
    ASSERT_TRUE(solveExact(s.model, sys, exact));

    Points dv, next;
    jacobiStart(sys, dv);
    Scalar previous = (dv - exact).norm() / exact.norm();
    // Until rounding level (~1e-15), every sweep must shrink the error.
    for (int k = 1; k <= 60 && previous > 1e-13; ++k) {
        jacobiSweep(s.model, sys, dv, next);
        std::swap(dv, next);
        const Scalar err = (dv - exact).norm() / exact.norm();
        EXPECT_LT(err, previous) << "iteration " << k;
        previous = err;
    }
    EXPECT_LT(previous, 1e-13);
    // The solver's own one-iteration dv has the same error as one sweep here.
    auto solver = solverOf("kangcho:iterations=1");
    State state = s.state;
    ASSERT_EQ(solver->step(s.model, env, state, input).status, StepStatus::Ok);
    Points d0, d1;
    jacobiStart(sys, d0);
    jacobiSweep(s.model, sys, d0, d1);
    const Scalar oneSweepError = (d1 - exact).norm() / exact.norm();
    EXPECT_NEAR(solveError({s.model, env, s.state, input, true}, solver->lastDv()), oneSweepError,
                1e-12);
}

TEST(Exact, ResidualBelow1e10AndMatrixSymmetricPositiveDefinite) {
    Scene s = deformedGrid(7, 5, 1e5, 11);  // stiff: W far from diagonal
    const Environment env;
    StepInput input;
    input.h = 1.0 / 30;
    LinearSystem sys;
    buildSystem({s.model, env, s.state, input, true}, sys);
    const Eigen::MatrixXd W = Eigen::MatrixXd(assembleMatrix(s.model, sys));
    EXPECT_LT((W - W.transpose()).norm(), 1e-15 * W.norm());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(W);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);

    // Some springs really are compressed, so eq. 17 is what keeps W positive definite.
    int compressed = 0;
    for (const Spring& sp : s.model.springs())
        compressed += (s.state.x.col(sp.j) - s.state.x.col(sp.i)).norm() < sp.rest;
    EXPECT_GT(compressed, 10);

    Points dv;
    Scalar residual = 1;
    ASSERT_TRUE(solveExact(s.model, sys, dv, &residual));
    EXPECT_LE(residual, 1e-10);
    // Independently: a dense solve of the same matrix.
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.rhs.data(), sys.rhs.size());
    const Eigen::VectorXd dense = W.ldlt().solve(b);
    EXPECT_LT((Eigen::Map<const Eigen::VectorXd>(dv.data(), dv.size()) - dense).norm(),
              1e-9 * dense.norm());
    EXPECT_LE(relativeResidual(s.model, sys, dv), 1e-10);

    for (const char* spec : {"exact", "cg:tolerance=1e-10"}) {
        auto solver = solverOf(spec);
        State state = s.state;
        const StepResult r = solver->step(s.model, env, state, input);
        ASSERT_EQ(r.status, StepStatus::Ok);
        EXPECT_LE(solveError({s.model, env, s.state, input, true}, solver->lastDv()), 1e-9) << spec;
    }
}

TEST(Pins, EnterTheirNeighboursEquations) {
    // A pinned particle's prescribed dv moves its free neighbours within the same step (through
    // J_ij dv_j), for the exact solve and for one Jacobi iteration alike.
    for (const char* spec : {"exact", "kangcho"}) {
        HangingFlagDesc d;
        d.nx = d.ny = 5;
        HangingFlag still = makeHangingFlag(d), moved = makeHangingFlag(d);
        Environment env;
        env.gravity.setZero();
        StepInput input;
        input.h = 1.0 / 60;
        const std::vector<Pin> pinsStill = pinColumn(still.model);
        // In the cloth's plane: a flat cloth at rest has no stiffness across its plane.
        const Vec3 offset(0.02, 0.05, 0);
        const std::vector<Pin> pinsMoved = pinColumn(moved.model, offset);
        auto a = solverOf(spec), b = solverOf(spec);
        input.pins = pinsStill;
        a->step(still.model, env, still.state, input);
        input.pins = pinsMoved;
        b->step(moved.model, env, moved.state, input);
        const Index neighbour = 1;  // column 1, row 0: next to pinned particle 0
        const Scalar along = (moved.state.x.col(neighbour) - still.state.x.col(neighbour)).dot(offset);
        EXPECT_GT(along, 1e-7) << spec;
    }
}

TEST(Stability, HangingFlagStableWithKangChoWhileExplicitBlowsUp) {
    HangingFlagDesc d;  // 33 x 33, k = 1e4 N/m
    const Environment env;
    StepInput input;
    input.h = 1.0 / 60;
    auto run = [&](const char* spec, int steps) -> int {  // the step it failed at, or -1
        HangingFlag flag = makeHangingFlag(d);
        input.pins = flag.pins;
        auto solver = solverOf(spec);
        for (int s = 0; s < steps; ++s) {
            if (solver->step(flag.model, env, flag.state, input).status != StepStatus::Ok) return s;
            if (s % 50 == 49 &&
                instability(measure(flag.model, env, flag.state), flag.state, d.poleTop))
                return s;
        }
        return instability(measure(flag.model, env, flag.state), flag.state, d.poleTop) ? steps : -1;
    };
    EXPECT_EQ(run("kangcho", 2000), -1);
    EXPECT_GE(run("explicit:substeps=1", 2000), 0);
}

TEST(Failure, NonFiniteInputIsReportedAndStateKept) {
    HangingFlagDesc d;
    d.nx = d.ny = 5;
    HangingFlag flag = makeHangingFlag(d);
    Points external = Points::Zero(3, flag.model.particleCount());
    external(1, 7) = std::numeric_limits<Scalar>::quiet_NaN();
    const State before = flag.state;
    StepInput input;
    input.pins = flag.pins;
    input.externalForce = &external;
    for (const char* spec : {"kangcho", "explicit", "cg"}) {
        auto solver = solverOf(spec);
        const StepResult r = solver->step(flag.model, Environment{}, flag.state, input);
        EXPECT_NE(r.status, StepStatus::Ok) << spec;
        EXPECT_TRUE(flag.state.x.allFinite() && flag.state.v.allFinite()) << spec;
        EXPECT_EQ(flag.state.x, before.x) << spec;
    }
}

TEST(SolverConfig, ParsesAndRejectsWithClearMessages) {
    SolverConfig c;
    std::string error;
    ASSERT_TRUE(parseSolverConfig("kangcho:iterations=4,compression=off", c, &error));
    EXPECT_EQ(describe(c), "kangcho:iterations=4,compression=off");
    EXPECT_FALSE(c.compressionRule);
    EXPECT_FALSE(parseSolverConfig("jacobi", c, &error));
    EXPECT_NE(error.find("unknown solver 'jacobi'"), std::string::npos);
    EXPECT_FALSE(parseSolverConfig("kangcho:iterations=-1", c, &error));
    EXPECT_NE(error.find("iterations"), std::string::npos);
    EXPECT_FALSE(parseSolverConfig("explicit:substeps=abc", c, &error));
    EXPECT_NE(error.find("'abc'"), std::string::npos);
    EXPECT_FALSE(parseSolverConfig("exact:substeps=2", c, &error));
    EXPECT_NE(error.find("no parameter 'substeps'"), std::string::npos);
}

// Symplectic Euler is stable for h < 2 / omega_max, omega_max^2 the largest eigenvalue of
// M^-1 K (K the stiffness matrix at rest). Computed here with a dense eigen-solve on a small
// pinned grid, then checked at 0.9 and 1.1 times the limit.
TEST(Explicit, BlowsUpAboveItsStabilityLimitAndNotBelow) {
    HangingFlagDesc d;
    d.nx = 6;
    d.ny = 5;
    d.stiffness = {2e3, 2e3, 200};
    HangingFlag flag = makeHangingFlag(d);
    Environment env;
    env.gravity.setZero();
    StepInput input;
    input.h = 1.0;
    input.pins = flag.pins;
    LinearSystem sys;
    buildSystem({flag.model, env, flag.state, input, true}, sys);
    // W = M + h^2 K with h = 1 on free rows: K = W - M.
    Eigen::MatrixXd K = Eigen::MatrixXd(assembleMatrix(flag.model, sys));
    const Index n = flag.model.particleCount();
    Eigen::VectorXd invSqrtM(3 * n);
    for (Index i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
            K(3 * i + a, 3 * i + a) -= sys.pinned[i] ? 1.0 : flag.model.masses()[i];
            invSqrtM(3 * i + a) = sys.pinned[i] ? 0.0 : 1 / std::sqrt(flag.model.masses()[i]);
        }
    }
    const Eigen::MatrixXd A = invSqrtM.asDiagonal() * K * invSqrtM.asDiagonal();  // M^-1/2 K M^-1/2
    const double omegaMax = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().maxCoeff());
    const double hCrit = 2 / omegaMax;
    auto blowsUp = [&](double h) {
        HangingFlag f = makeHangingFlag(d);
        // A small, deterministic kick excites every mode.
        for (Index i = 0; i < n; ++i) f.state.v.col(i) = Vec3(0.01 * std::sin(i), 0.01 * std::cos(3 * i), 0.01 * std::sin(7 * i));
        auto solver = solverOf("explicit:substeps=1");
        StepInput in;
        in.h = h;
        in.pins = f.pins;
        for (int s = 0; s < 3000; ++s) {
            if (solver->step(f.model, env, f.state, in).status != StepStatus::Ok) return true;
            if (instability(measure(f.model, env, f.state), f.state, d.poleTop)) return true;
        }
        return false;
    };
    EXPECT_FALSE(blowsUp(0.9 * hCrit)) << "h_crit = " << hCrit;
    EXPECT_TRUE(blowsUp(1.1 * hCrit)) << "h_crit = " << hCrit;
}

// Desbrun et al.'s filter: dv solves (M + h^2 k L) dv = h f - h^2 k L v, L the graph Laplacian,
// here assembled densely and independently of the solver.
TEST(Desbrun, StepSolvesTheConstantLaplacianSystem) {
    Scene s = deformedGrid(5, 4, 300.0, 5);
    Environment env;
    StepInput input;
    input.h = 1.0 / 60;
    const Index n = s.model.particleCount();
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
    for (Index i = 0; i < n; ++i) A(i, i) = s.model.masses()[i];
    Eigen::MatrixXd kL = Eigen::MatrixXd::Zero(n, n);
    for (const Spring& sp : s.model.springs()) {
        kL(sp.i, sp.i) += sp.k, kL(sp.j, sp.j) += sp.k;
        kL(sp.i, sp.j) -= sp.k, kL(sp.j, sp.i) -= sp.k;
    }
    const double h = input.h;
    A += h * h * kL;
    Points f;
    computeForces(s.model, env, s.state, nullptr, f);
    const Eigen::MatrixXd b = h * f.transpose() - h * h * kL * s.state.v.transpose();
    const Eigen::MatrixXd expected = A.ldlt().solve(b).transpose();
    auto solver = solverOf("desbrun");
    State state = s.state;
    ASSERT_EQ(solver->step(s.model, env, state, input).status, StepStatus::Ok);
    EXPECT_LT((solver->lastDv() - expected).norm(), 1e-10 * expected.norm());
}
