// Implicit air against central finite differences and the system every implicit solver reads;
// the multigrid kind's keys and the solver configs' text form read back.

#include <gtest/gtest.h>

#include <cstring>

#include "cloth/air.h"
#include "cloth/paper_step.h"
#include "cloth/presets.h"
#include "cloth/solver_kind.h"
#include "multigrid_case.h"
#include "solver_spec.h"

using namespace cloth;
using namespace cloth::test;

TEST(SolverConfig, MultigridKeysAreWhatAUserChoosesAndItsTuningIsChecked) {
    SolverConfig c;
    std::string error;
    ASSERT_TRUE(parseSolverConfig("multigrid", c, &error)) << error;
    EXPECT_EQ(c.get<MultigridSettings>().tolerance, 1.5e-3);
    EXPECT_EQ(c.get<MultigridSettings>().maxCycles, 16);
    EXPECT_EQ(c.get<MultigridSettings>().cycles, 0);
    EXPECT_EQ(settledTuning(c.get<MultigridSettings>()).kcycleLevels, 1);  // a K-cycle on level 1 when adaptive
    ASSERT_TRUE(parseSolverConfig("multigrid:cycles=2", c, &error)) << error;
    EXPECT_EQ(settledTuning(c.get<MultigridSettings>()).kcycleLevels, 0);  // ... and a V-cycle for a fixed count
    // At most six keys of its own; the tuning is not among them.
    const SolverKind* kind = findSolverKind("multigrid");
    ASSERT_TRUE(kind);
    int own = 0;
    for (const SolverKey& k : kind->keys) {
        const std::string name = k.name;
        own += name != "compression";
    }
    EXPECT_LE(own, 6);
    for (const char* key : {"kcycle=1", "pre_sweeps=2", "damping=0.5", "start=zero", "coarse=rediscretize"}) {
        EXPECT_FALSE(parseSolverConfig(std::string("multigrid:") + key, c, &error)) << key;
        EXPECT_NE(error.find(std::string(key).substr(0, std::string(key).find('='))), std::string::npos) << error;
    }
    EXPECT_FALSE(parseSolverConfig("multigrid:precision=float,tolerance=1e-10", c, &error));
    EXPECT_NE(error.find("precision=float"), std::string::npos) << error;
    ASSERT_TRUE(parseSolverConfig("multigrid:precision=mixed", c, &error)) << error;
    MultigridTuning t = settledTuning(c.get<MultigridSettings>());
    t.krylov = false;
    c.get<MultigridSettings>().tuning = t;
    EXPECT_NE(validate(c).find("precision = mixed"), std::string::npos) << validate(c);
    t.krylov = true;
    t.preSweeps = t.postSweeps = 0;
    c.get<MultigridSettings>().tuning = t;
    EXPECT_NE(validate(c).find("smoothing sweeps"), std::string::npos) << validate(c);
}

// Implicit air: the velocity Jacobian's diagonal blocks against central differences of the air
// force, and what W gets from them.
TEST(ImplicitAir, VelocityJacobianEqualsACentralDifferenceOfTheAirForce) {
    const Case c = stiffCase(7, 6, false, 21);
    AirParams air;
    air.wind = Vec3(12, 3, -7);
    Points f = Points::Zero(3, c.model.particleCount());
    std::vector<Mat3> jac;
    addAirForces(c.model, c.state, air, f, &jac);
    const Scalar eps = 1e-6;
    Scalar worst = 0, scale = 0;
    for (Index i = 0; i < c.model.particleCount(); ++i) {
        Mat3 fd;
        for (int a = 0; a < 3; ++a) {
            State plus = c.state, minus = c.state;
            plus.v(a, i) += eps;
            minus.v(a, i) -= eps;
            Points fp = Points::Zero(3, c.model.particleCount()), fm = fp;
            addAirForces(c.model, plus, air, fp);
            addAirForces(c.model, minus, air, fm);
            fd.col(a) = (fp.col(i) - fm.col(i)) / (2 * eps);
        }
        worst = std::max(worst, (fd - jac[i]).norm());
        scale = std::max(scale, fd.norm());
    }
    EXPECT_GT(scale, 1e-4);  // the air does act
    EXPECT_LT(worst, 1e-6 * scale);
}

TEST(ImplicitAir, WGetsTheSymmetricPositivePartOfMinusDfDvTimesH) {
    const Case c = stiffCase(7, 6, false, 22);
    AirParams air;
    air.wind = Vec3(-20, 5, 9);
    Points f = Points::Zero(3, c.model.particleCount());
    std::vector<Mat3> jac, damping;
    addAirForces(c.model, c.state, air, f, &jac);
    airDamping(jac, damping);
    const Scalar h = 1.0 / 240;
    StepInput in = inputOf(c, h);
    LinearSystem without, with;
    buildSystem({c.model, {}, c.state, in, true}, without);
    in.damping = &damping;
    buildSystem({c.model, {}, c.state, in, true}, with);
    for (Index i = 0; i < c.model.particleCount(); ++i) {
        if (without.pinned[i]) continue;
        // Independently: the symmetric part of -df/dv, eigenvalues clamped at zero.
        const Mat3 sym = -0.5 * (jac[i] + jac[i].transpose());
        Eigen::SelfAdjointEigenSolver<Mat3> eig(sym);
        const Mat3 expected =
            eig.eigenvectors() * eig.eigenvalues().cwiseMax(0).asDiagonal() * eig.eigenvectors().transpose();
        EXPECT_LT(((with.diag[i] - without.diag[i]) / h - expected).norm(), 1e-9 * (1 + expected.norm())) << i;
        EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(damping[i]).eigenvalues().minCoeff(), -1e-12);
    }
}

TEST(ImplicitAir, EveryImplicitSolverReadsTheSameDampedSystem) {
    // With a large damping (light particles in a gale), the fast paths, multigrid and the reference
    // must agree: all of them read W_ii + h C_i.
    Case c = stiffCase(13, 9, false, 23);
    AirParams air;
    air.wind = Vec3(40, 0, 5);
    Points f = Points::Zero(3, c.model.particleCount());
    std::vector<Mat3> jac, damping;
    addAirForces(c.model, c.state, air, f, &jac);
    airDamping(jac, damping);
    c.external = f;
    auto dvWith = [&](const std::string& spec) {
        auto solver = solverOf(spec);
        State state = c.state;
        StepInput in = inputOf(c);
        in.damping = &damping;
        EXPECT_EQ(solver->step(c.model, {}, state, in).status, StepStatus::Ok) << spec;
        return Points(solver->lastDv());
    };
    const Points ref = dvWith("kangcho:iterations=2,impl=reference");
    for (const char* spec : {"kangcho:iterations=2", "kangcho:iterations=2,impl=gather"})
        EXPECT_LT((dvWith(spec) - ref).norm() / ref.norm(), 1e-12) << spec;
    const Points exact = dvWith("exact");
    EXPECT_LT((dvWith("exact:method=multigrid") - exact).norm() / exact.norm(), 1e-8);
    // And the damping changes the answer (the test would pass trivially if it were ignored).
    auto plain = solverOf("exact");
    State state = c.state;
    plain->step(c.model, {}, state, inputOf(c));
    EXPECT_GT((plain->lastDv() - exact).norm() / exact.norm(), 1e-3);
}

TEST(SolverConfig, DescribeParsesBackToTheSameConfig) {
    // The study labels rows with describe() and re-parses it: the text must mean the same solver.
    for (const char* spec : {"kangcho", "kangcho:iterations=3,impl=gather,precision=float,threads=2",
                             "exact", "exact:method=multigrid", "cg:tolerance=1e-6", "multigrid",
                             "multigrid:cycles=2,max_cycles=3,tolerance=0.01", "multigrid:precision=float,threads=2",
                             "multigrid:precision=mixed", "chebyshev:iterations=4", "explicit:substeps=3",
                             "desbrun"}) {
        SolverConfig a, b;
        std::string error;
        ASSERT_TRUE(parseSolverConfig(spec, a, &error)) << spec << ": " << error;
        ASSERT_TRUE(parseSolverConfig(describe(a), b, &error)) << describe(a) << ": " << error;
        EXPECT_EQ(describe(a), describe(b)) << spec;
        // A key that differs from its default is in the text (else two solvers share a label).
        if (std::string(spec).find("precision=") != std::string::npos) {
            EXPECT_NE(describe(a).find("precision="), std::string::npos) << describe(a);
        }
    }
}
