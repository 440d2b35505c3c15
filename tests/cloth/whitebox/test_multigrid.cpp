// Multigrid's components (cloth/src/multigrid/) against independent computations: the system
// assembled by the reference path (system.cpp) and solved densely or by sparse Cholesky, dense
// triple products; the solver's warm start, reuse, threads and precisions.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstring>
#include <random>

#include "cloth/paper_step.h"
#include "cloth/presets.h"
#include "cloth/solver_kind.h"
#include "multigrid/multigrid.h"
#include "multigrid_case.h"
#include "solver_spec.h"

using namespace cloth;
using namespace cloth::test;

TEST(Multigrid, OneVCycleReducesTheResidualOfARandomRightHandSideFivefold) {
    // A V(2,2) cycle (two sweeps before and after) must reduce the residual at least 5x on every
    // cloth: that measures the hierarchy. The default V(1,1) cycle (cheaper per CG iteration, and
    // on the vehicle path as accurate at the same tolerance) must reduce it 5x on grids and 3x on
    // meshes, where smoothed aggregation leaves more to the smoother (measured: 5.9-6.2x on the
    // grids below, 3.3-3.5x on the meshes; V(2,2): 14-16x and 5.6-6.2x).
    // (On a rough state, with a random ripple of 5% of the spacing in every direction, the grid's
    // V(2,2) reduction falls to about 4x: bilinear interpolation does not represent a crumpled
    // sheet's low-energy modes. That is why the solver wraps the cycles in conjugate gradients.)
    for (const Size s : {Size{17, 17, false}, Size{65, 65, false}, Size{33, 22, false}, Size{40, 27, false},
                         Size{25, 17, true}, Size{41, 33, true}}) {
        const Case c = stiffCase(s.nx, s.ny, s.mesh, 3);
        LinearSystem sys;
        buildSystem({c.model, {}, c.state, inputOf(c), true}, sys);
        const Eigen::SparseMatrix<Scalar> W = assembleMatrix(c.model, sys);
        for (const int sweeps : {2, MultigridTuning{}.preSweeps}) {
            Multigrid<double> mg(tuned({}, [&](MultigridTuning& t) { t.preSweeps = t.postSweeps = sweeps; }));
            mg.prepareSystem({c.model, {}, c.state, inputOf(c), true});
            std::mt19937 rng(11);
            std::normal_distribution<Scalar> normal;
            Eigen::VectorXd b(3 * c.model.particleCount());
            for (Index q = 0; q < b.size(); ++q) b[q] = sys.pinned[q / 3] ? 0.0 : normal(rng);
            const Eigen::VectorXd x = mg.vcycle(b);
            const Scalar reduction = (b - W * x).norm() / b.norm();
            const Scalar required = sweeps >= 2 || !s.mesh ? 5 : 3;
            EXPECT_LT(reduction * required, 1) << s.nx << "x" << s.ny << (s.mesh ? " mesh" : " grid") << ", V("
                                               << sweeps << "," << sweeps << "), levels " << mg.describeHierarchy();
            EXPECT_GE(mg.levels(), 3) << mg.describeHierarchy();
        }
    }
}

// W with every bend spring (i, j = i + 2 d along a grid line, midpoint m) replaced by two springs
// (i, m) and (m, j) with twice its block, computed densely from the reference W's block W_ij, with
// pinned rows and columns zeroed again: the matrix multigrid's coarse levels are built from when
// bend springs are collapsed.
Eigen::MatrixXd denselyCollapsed(const Case& c, const LinearSystem& sys, const Eigen::MatrixXd& W) {
    Eigen::MatrixXd S = W;
    for (const Spring& sp : c.model.springs()) {
        if (sp.kind != SpringKind::Bend) continue;
        const Index i = sp.i, j = sp.j, m = (i + j) / 2;
        const Eigen::Matrix3d O = W.block<3, 3>(3 * i, 3 * j);
        auto add = [&](Index r, Index q, const Eigen::Matrix3d& B) { S.block<3, 3>(3 * r, 3 * q) += B; };
        add(i, j, -O), add(j, i, -O);
        add(i, m, 2 * O), add(m, i, 2 * O), add(m, j, 2 * O), add(j, m, 2 * O);
        add(i, i, -O), add(j, j, -O), add(m, m, -4 * O);
    }
    for (Index i = 0; i < c.model.particleCount(); ++i)
        if (sys.pinned[i]) {
            S.middleRows(3 * i, 3).setZero();
            S.middleCols(3 * i, 3).setZero();
        }
    return S;
}

TEST(Multigrid, GalerkinCoarseOperatorEqualsTheDenseTripleProduct) {
    // 11x8: the plan on every level (an even side); 21x17 -> 11x9 -> 6x5 -> 3x3: the stencil
    // product from the cloth's bands (level 0) and from a Galerkin level's bands (level 1), then
    // the plan; 25x15 -> 13x8: by stencil into a banded level that a plan then reads (its block
    // copy filled from the bands); the mesh: aggregation, the plan. On grids the bend springs are
    // collapsed onto their halves for the coarse levels (level 1 is P^T S P with S from
    // denselyCollapsed).
    struct Path {
        Size s;
        const char* path;  // in describeHierarchy()
    };
    for (const auto& [s, path] : {Path{{11, 8, false}, "(Galerkin"}, Path{{21, 17, false}, "by stencil on 2 of 3 coarse levels"},
                                   Path{{25, 15, false}, "by stencil on 1 of"}, Path{{11, 8, true}, "(Galerkin)"}}) {
        const bool mesh = s.mesh;
        Case c = stiffCase(s.nx, s.ny, mesh, 5);
        // And one pinned particle inside, whose bend springs' ends are free.
        const Index inner = 2 * s.nx + 3;
        c.pins.push_back({inner, c.state.x.col(inner), Vec3(0, 1, 0)});
        LinearSystem sys;
        Environment env;
        env.drag = 0.5;
        buildSystem({c.model, env, c.state, inputOf(c), true}, sys);
        // by stencil on grids this small too
        Multigrid<double> mg(tuned({}, [](MultigridTuning& t) { t.stencilGalerkinMinRow = 0; }));
        mg.prepareSystem({c.model, env, c.state, inputOf(c), true});
        mg.vcycle(Eigen::VectorXd::Zero(3 * c.model.particleCount()));  // builds the coarse levels
        ASSERT_GE(mg.levels(), 2);
        const std::string hierarchy = mg.describeHierarchy();
        EXPECT_NE(hierarchy.find(path), std::string::npos) << hierarchy;
        EXPECT_EQ(hierarchy.find("with bend springs collapsed") != std::string::npos, !mesh) << hierarchy;
        // Level 0 is the reference W of the free particles.
        const Eigen::MatrixXd W = referenceFreeMatrix(c, sys);
        EXPECT_LT((mg.matrix(0).dense() - W).norm(), 1e-10 * W.norm()) << (mesh ? "mesh" : "grid");
        Eigen::MatrixXd A = !mesh ? denselyCollapsed(c, sys, W) : W;
        for (int l = 0; l + 1 < mg.levels(); ++l) {
            const Eigen::MatrixXd P = mg.prolongation(l);
            // Interpolation reproduces constants: every row of P sums to one.
            const Eigen::VectorXd rowSums = P.rowwise().sum();
            EXPECT_LT((rowSums.array() - 1).abs().maxCoeff(), 1e-12) << "level " << l;
            A = P.transpose() * A * P;
            EXPECT_LT((mg.matrix(l + 1).dense() - A).norm(), 1e-10 * A.norm())
                << (mesh ? "mesh " : "grid ") << s.nx << "x" << s.ny << " level " << l + 1 << ", " << hierarchy;
        }
    }
}

TEST(Multigrid, AKCycleLevelReturnsTheEnergyMinimizerOverItsTwoCycles) {
    // On a K-cycle level, the coarse solve is two flexible CG iterations: c1 = B b, c2 = B (b - t1
    // W c1) with t1 = c1.b / c1.W c1 (B: one cycle from that level, the same with or without the
    // K-cycle above it), and the answer is the x in span{c1, c2} closest to W^-1 b in the W-norm.
    // Here c1 and c2 come from a V-cycle solver, and the minimizer from the dense 2x2 projection.
    for (const Size s : {Size{65, 65, false}, Size{40, 27, false}, Size{41, 33, true}}) {
        const Case c = stiffCase(s.nx, s.ny, s.mesh, 5);
        Multigrid<double> v(tuned({}, [](MultigridTuning& t) { t.kcycleLevels = 0; }));
        Multigrid<double> k(tuned({}, [](MultigridTuning& t) { t.kcycleLevels = 1; }));
        v.prepareSystem({c.model, {}, c.state, inputOf(c), true});
        k.prepareSystem({c.model, {}, c.state, inputOf(c), true});
        k.vcycle(Eigen::VectorXd::Zero(3 * c.model.particleCount()));  // builds the coarse levels
        ASSERT_GE(k.levels(), 3) << k.describeHierarchy();
        const Eigen::MatrixXd A = k.matrix(1).dense();
        std::mt19937 rng(17);
        std::normal_distribution<Scalar> normal;
        Eigen::VectorXd b(A.rows());
        for (Index q = 0; q < b.size(); ++q) b[q] = A.row(q).isZero() ? 0.0 : normal(rng);  // empty rows: no unknown
        const Eigen::VectorXd x = k.coarseSolve(1, b);
        const Eigen::VectorXd c1 = v.coarseSolve(1, b);
        const Eigen::VectorXd c2 = v.coarseSolve(1, b - (c1.dot(b) / c1.dot(A * c1)) * A * c1);
        Eigen::Matrix2d G;
        G << c1.dot(A * c1), c1.dot(A * c2), c2.dot(A * c1), c2.dot(A * c2);
        const Eigen::Vector2d y = G.ldlt().solve(Eigen::Vector2d(c1.dot(b), c2.dot(b)));
        const Eigen::VectorXd best = y[0] * c1 + y[1] * c2;
        EXPECT_LT((x - best).norm() / best.norm(), 1e-9) << s.nx << "x" << s.ny << (s.mesh ? " mesh" : " grid");
        // ... and it leaves a smaller residual than the one cycle of a V-cycle level (the projection
        // minimizes the energy norm of the error, not the residual, so this is measured, not implied).
        EXPECT_LT((b - A * x).norm(), (b - A * c1).norm()) << s.nx << "x" << s.ny;
    }
}

TEST(Multigrid, ToTenToTheMinusTenEqualsTheCholeskySolve) {
    // 65x11: the Galerkin product by stencil from level 0 (rows of 33 coarse points).
    for (const Size s : {Size{33, 21, false}, Size{33, 21, true}, Size{65, 11, false}}) {
        const bool mesh = s.mesh;
        const Case c = stiffCase(s.nx, s.ny, mesh, 9);
        Environment env;
        env.drag = 0.2;
        const Points chol = stepDv("exact", c, env);
        EXPECT_LT((stepDv("exact:method=multigrid", c, env) - chol).norm() / chol.norm(), 1e-8) << (mesh ? " mesh" : " grid");
        for (const char* spec : {"multigrid:tolerance=1e-10,max_cycles=200", "multigrid:tolerance=1e-10,max_cycles=200,precision=mixed"})
            for (const int kcycle : {0, 1, 2}) {
                const Points mg = stepDv(spec, c, env, [&](MultigridTuning& t) { t.kcycleLevels = kcycle; });
                EXPECT_LT((mg - chol).norm() / chol.norm(), 1e-8) << spec << " kcycle " << kcycle << (mesh ? " mesh" : " grid");
            }
    }
}

TEST(Multigrid, AdaptiveCyclesStopAtTheToleranceAndReportTheCount) {
    const Case c = stiffCase(33, 33, false, 4);
    LinearSystem sys;
    buildSystem({c.model, {}, c.state, inputOf(c), true}, sys);
    for (const double tol : {1e-1, 1e-2, 1e-4}) {
        auto solver = solverOf("multigrid:tolerance=" + std::to_string(tol) + ",max_cycles=50");
        State state = c.state;
        const StepResult r = solver->step(c.model, {}, state, inputOf(c));
        ASSERT_EQ(r.status, StepStatus::Ok);
        // The reported residual is the reference path's (pinned rows hold their prescribed dv).
        EXPECT_LE(relativeResidual(c.model, sys, solver->lastDv()), tol) << tol;
        EXPECT_GE(r.iterations, 1);
        EXPECT_LT(r.iterations, 50);
        if (tol == 1e-4) {
            EXPECT_GT(r.iterations, 1);
        }
    }
    // A fixed count is a fixed count.
    auto two = solverOf("multigrid:cycles=2");
    State state = c.state;
    EXPECT_EQ(two->step(c.model, {}, state, inputOf(c)).iterations, 2);
}

// max_i |W_ii^-1 r_i| / max_i |dv_i| over the free particles, with r = b - W dv from the
// reference path's system (its diagonal blocks, their inverses and its off-diagonal product).
double largestJacobiCorrection(const Case& c, const LinearSystem& sys, const Points& dv) {
    Points off;
    applyOffDiagonal(c.model, sys, dv, off);
    double correction = 0, largest = 0;
    for (Index i = 0; i < c.model.particleCount(); ++i) {
        if (sys.pinned[i]) continue;
        const Vec3 r = sys.rhs.col(i) - (sys.diag[i] * dv.col(i) - off.col(i));
        correction = std::max(correction, (sys.diagInv[i] * r).norm());
        largest = std::max(largest, dv.col(i).norm());
    }
    return correction / largest;
}

TEST(Multigrid, TheLocalToleranceBoundsEveryParticlesJacobiCorrection) {
    // A wave front in miniature: the solver has solved this state, and now a 3x3 patch in the
    // middle of the flag is pushed. From the previous dv (the warm start) the residual is that
    // patch's alone, and its norm is small next to |b| of the whole cloth.
    const Case c = stiffCase(33, 33, false, 6);
    Case pushed = c;
    for (int row = 15; row < 18; ++row)
        for (int col = 15; col < 18; ++col) pushed.external.col(row * 33 + col) += Vec3(0, 0, 6);
    LinearSystem sys;
    buildSystem({pushed.model, {}, pushed.state, inputOf(pushed), true}, sys);
    for (const std::string options : {"", " stationary", ",precision=mixed"}) {
        const std::string spec = "multigrid:tolerance=1e-2,max_cycles=100" + (options[0] == ',' ? options : "");
        const bool krylov = options != " stationary";
        auto off = solverFor(spec, [&](MultigridTuning& t) { t.localTolerance = 0, t.krylov = krylov; });
        auto on = solverFor(spec, [&](MultigridTuning& t) { t.localTolerance = 1e-2, t.krylov = krylov; });
        StepResult r[2];
        for (int k = 0; k < 2; ++k) {
            Solver& solver = k ? *on : *off;
            State state = c.state;
            ASSERT_EQ(solver.step(c.model, {}, state, inputOf(c)).status, StepStatus::Ok) << spec;
            state = pushed.state;
            r[k] = solver.step(pushed.model, {}, state, inputOf(pushed));
            ASSERT_EQ(r[k].status, StepStatus::Ok) << spec;
        }
        // Without it the relative residual alone stops the solve with a larger local correction
        // left (else this case would not test the local tolerance) ...
        EXPECT_GT(largestJacobiCorrection(pushed, sys, off->lastDv()), 1e-2) << spec;
        // ... with it both hold, in the reference path's own terms, at the price of more cycles.
        EXPECT_LE(largestJacobiCorrection(pushed, sys, on->lastDv()), 1e-2) << spec;
        EXPECT_LE(relativeResidual(pushed.model, sys, on->lastDv()), 1e-2) << spec;
        EXPECT_GT(r[1].iterations, r[0].iterations) << spec;
    }
}

TEST(Multigrid, AWarmStartMeetsTheToleranceInFewerCyclesAndInNoMoreThanAColdOneAfterAJump) {
    // The hanging flag (vertical, pinned along its pole) sagging under gravity from rest.
    HangingFlagDesc d;
    d.nx = d.ny = 33;
    HangingFlag flag = makeHangingFlag(d);
    const double tol = 1e-4;
    const std::string spec = "multigrid:tolerance=1e-4,max_cycles=50";
    auto warm = solverOf(spec);  // settled: the last solves when adaptive
    const Tune zero = [](MultigridTuning& t) { t.startHistory = 0; };
    StepInput in;
    in.h = 1.0 / 240;
    in.pins = flag.pins;
    int warmCycles = 0, coldCycles = 0;
    for (int k = 0; k < 10; ++k) {
        LinearSystem sys;
        buildSystem({flag.model, {}, flag.state, in, true}, sys);
        auto cold = solverFor(spec, zero);
        State coldState = flag.state;
        const StepResult rc = cold->step(flag.model, {}, coldState, in);
        const StepResult rw = warm->step(flag.model, {}, flag.state, in);
        ASSERT_EQ(rw.status, StepStatus::Ok);
        EXPECT_LE(relativeResidual(flag.model, sys, warm->lastDv()), tol) << k;
        if (k > 0) warmCycles += rw.iterations, coldCycles += rc.iterations;
    }
    EXPECT_LT(warmCycles, coldCycles);
    // The same system again: the previous dv already meets the tolerance, so no cycle runs.
    State again = flag.state;
    warm->step(flag.model, {}, again, in);
    again = flag.state;
    EXPECT_EQ(warm->step(flag.model, {}, again, in).iterations, 0);
    {
        LinearSystem sys;
        buildSystem({flag.model, {}, flag.state, in, true}, sys);
        EXPECT_LE(relativeResidual(flag.model, sys, warm->lastDv()), tol);
    }
    // A jump: a side force of 100 N per particle. The last solves' dv are far from the new one,
    // and their best combination is nearly nothing: the solve meets the tolerance in about the
    // cycles a cold solve takes (never worse in the energy norm than starting from zero).
    const Points push = Points::Constant(3, flag.model.particleCount(), 100.0);
    in.externalForce = &push;
    auto cold = solverFor(spec, zero);
    State coldState = flag.state;
    const StepResult rc = cold->step(flag.model, {}, coldState, in);
    {
        LinearSystem sys;
        buildSystem({flag.model, {}, flag.state, in, true}, sys);
        const StepResult rw = warm->step(flag.model, {}, flag.state, in);
        EXPECT_LE(rw.iterations, rc.iterations);
        EXPECT_LE(relativeResidual(flag.model, sys, warm->lastDv()), tol);
    }
    // A fixed count starts from zero unless asked: the same bits as a fresh solver's.
    const Case c = stiffCase(33, 33, false, 4);
    auto fixed = solverOf("multigrid:cycles=1");
    State a = c.state;
    fixed->step(c.model, {}, a, inputOf(c));
    State b = a;
    fixed->step(c.model, {}, a, inputOf(c));
    auto fresh = solverOf("multigrid:cycles=1");
    fresh->step(c.model, {}, b, inputOf(c));
    EXPECT_EQ(fixed->lastDv(), fresh->lastDv());
}

TEST(Multigrid, OneFixedCycleRunsAloneUnlessCgIsAskedFor) {
    // Settled: one fixed cycle is the cycle alone (the stationary iteration's one step), not CG's
    // one iteration, which scales it by a step length; two cycles run under CG.
    const Case c = stiffCase(33, 33, false, 3);
    auto dvOf = [&](const std::string& spec, int krylov = -1) {
        auto solver = krylov < 0 ? solverOf(spec) : solverFor(spec, [&](MultigridTuning& t) { t.krylov = krylov == 1; });
        State s = c.state;
        EXPECT_EQ(solver->step(c.model, {}, s, inputOf(c)).status, StepStatus::Ok) << spec;
        return solver->lastDv();
    };
    EXPECT_EQ(dvOf("multigrid:cycles=1"), dvOf("multigrid:cycles=1", 0));
    EXPECT_NE(dvOf("multigrid:cycles=1"), dvOf("multigrid:cycles=1", 1));
    EXPECT_EQ(dvOf("multigrid:cycles=2"), dvOf("multigrid:cycles=2", 1));
    EXPECT_NE(dvOf("multigrid:cycles=2"), dvOf("multigrid:cycles=2", 0));
    // Float cycles need CG: one mixed-precision cycle still runs under it.
    EXPECT_EQ(dvOf("multigrid:cycles=1,precision=mixed"), dvOf("multigrid:cycles=1,precision=mixed", 1));
}

TEST(Multigrid, TwoPreviousSolvesSpanALinearlyChangingSolutionSoEachSolveNeedsAtMostOneCycle) {
    // One state, its system solved again and again with an external force that grows by the same
    // step each time: the exact dv_n = W^-1 b_n is linear in n, so dv_n = 2 dv_{n-1} - dv_{n-2}
    // lies in the span of the last two solves, and the start that minimizes the error's energy
    // norm over that span finds it. One previous solve alone cannot (dv_n is no multiple of it).
    // The solves stop on the relative residual alone, at 1e-8.
    const Case c = stiffCase(33, 33, false, 5);
    const int n = c.model.particleCount();
    auto run = [&](int history, double* residual) {
        auto solver = solverFor("multigrid:tolerance=1e-8", [&](MultigridTuning& t) {
            t.localTolerance = 0;
            t.startHistory = history;
        });
        int cycles = 0;
        for (int k = 0; k < 6; ++k) {
            Points force(3, n);
            for (int i = 0; i < n; ++i)
                force.col(i) = Eigen::Vector3d(2.0 * k, 1.0 * (i % 7), -1.5 * k * (i % 3));
            StepInput in = inputOf(c);
            in.externalForce = &force;
            State s = c.state;
            const StepResult r = solver->step(c.model, {}, s, in);
            EXPECT_EQ(r.status, StepStatus::Ok) << history << " " << k;
            if (k >= 3) cycles += r.iterations;
            LinearSystem sys;
            buildSystem({c.model, {}, c.state, in, true}, sys);
            *residual = std::max(*residual, relativeResidual(c.model, sys, solver->lastDv()));
        }
        return cycles;
    };
    double one = 0, two = 0;
    // Steps 3-5 start within the last solves' errors (1e-8) of the answer: at most one cycle each
    // (measured 0, 1, 0), where one previous solve takes 9-10 each.
    EXPECT_LE(run(2, &two), 3);
    EXPECT_GE(run(1, &one), 15);
    EXPECT_LE(one, 1e-8);
    EXPECT_LE(two, 1e-8);
}

TEST(Multigrid, ReusedCoarseOperatorsStillReachTheToleranceAndAreRebuiltWhenThePinsChange) {
    // The hanging flag sagging under gravity from rest, its coarse operators rebuilt every 8th step.
    HangingFlagDesc d;
    d.nx = d.ny = 33;
    HangingFlag flag = makeHangingFlag(d);
    StepInput in;
    in.h = 1.0 / 240;
    in.pins = flag.pins;
    const double tol = 1e-4;
    auto lagged = solverFor("multigrid:tolerance=1e-4,max_cycles=50", [](MultigridTuning& t) { t.coarseEvery = 8; });
    auto lagged1 = solverFor("multigrid:cycles=1", [](MultigridTuning& t) { t.coarseEvery = 1000; });
    State oneCycle = flag.state;
    for (int k = 0; k < 10; ++k) {
        // The residual of the reference path's system at this step, not the solver's own.
        LinearSystem sys;
        buildSystem({flag.model, {}, flag.state, in, true}, sys);
        ASSERT_EQ(lagged->step(flag.model, {}, flag.state, in).status, StepStatus::Ok);
        EXPECT_LE(relativeResidual(flag.model, sys, lagged->lastDv()), tol) << k;
        ASSERT_EQ(lagged1->step(flag.model, {}, oneCycle, in).status, StepStatus::Ok);
    }
    // The reuse is real: after 10 steps one cycle with the first step's coarse operators is not
    // one cycle with the current ones.
    auto fresh = solverOf("multigrid:cycles=1");
    State a = oneCycle, b = oneCycle;
    lagged1->step(flag.model, {}, a, in);
    fresh->step(flag.model, {}, b, in);
    EXPECT_NE(lagged1->lastDv(), fresh->lastDv());
    // Releasing a pin rebuilds them: the same bits as a solver that has never reused anything.
    in.pins.pop_back();
    a = oneCycle, b = oneCycle;
    lagged1->step(flag.model, {}, a, in);
    auto fresher = solverOf("multigrid:cycles=1");
    fresher->step(flag.model, {}, b, in);
    EXPECT_EQ(lagged1->lastDv(), fresher->lastDv());
}

TEST(Multigrid, OneAndTwoThreadsAreBitIdentical) {
    for (const Size s : {Size{37, 29, false}, Size{37, 29, true}, Size{65, 11, false}})
        for (const int kcycle : {0, 1})
            for (const char* precision : {"double", "float", "mixed"}) {
                const bool mesh = s.mesh;
                const Case c = stiffCase(s.nx, s.ny, mesh, 2);
                std::vector<State> finals;
                for (const int threads : {1, 2}) {
                    auto solver = solverFor(std::string("multigrid:precision=") + precision + ",threads=" + std::to_string(threads),
                                            [&](MultigridTuning& t) { t.kcycleLevels = kcycle; });
                    State state = c.state;
                    for (int k = 0; k < 5; ++k)
                        ASSERT_EQ(solver->step(c.model, {}, state, inputOf(c)).status, StepStatus::Ok);
                    finals.push_back(state);
                }
                const auto bytes = sizeof(Scalar) * std::size_t(finals[0].x.size());
                EXPECT_EQ(std::memcmp(finals[0].x.data(), finals[1].x.data(), bytes), 0) << kcycle << precision << mesh << s.nx;
                EXPECT_EQ(std::memcmp(finals[0].v.data(), finals[1].v.data(), bytes), 0) << kcycle << precision << mesh << s.nx;
            }
}

TEST(Multigrid, FloatPrecisionFollowsTheDoubleSolve) {
    const Case c = stiffCase(33, 33, false, 8);
    const Points d = stepDv("multigrid:cycles=3", c);
    const Points f = stepDv("multigrid:cycles=3,precision=float", c);
    EXPECT_LT((d - f).norm() / d.norm(), 1e-4);
    // Cycles in float under the double CG (level 0 rounded from the double system, coarse levels
    // built from it): the same to the float cycles' rounding, on a grid and on a mesh.
    for (const bool mesh : {false, true}) {
        const Case k = stiffCase(33, 25, mesh, 8);
        const Points dd = stepDv("multigrid:cycles=3", k), m = stepDv("multigrid:cycles=3,precision=mixed", k);
        EXPECT_LT((dd - m).norm() / dd.norm(), 1e-4) << mesh;
        EXPECT_GT((dd - m).norm(), 0.0) << mesh;  // the float hierarchy did run
    }
}

