// The air (cloth/air.h) against the per-triangle force formula it documents, evaluated here by
// hand; threads give the same bits; no force when the air moves with the cloth; the damping
// block's closed form against an eigen-decomposition.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "physics_support.h"
#include "cloth/air.h"
#include "cloth/presets.h"
#include "cloth/thread_pool.h"

using namespace cloth;
using namespace cloth::test;

namespace {

// ---------------------------------------------------------------------------------------------
// Air

// The force on one triangle as air.h documents it: area A, unit normal n oriented with the flow
// (w . n >= 0), relative air velocity w = wind - mean corner velocity, s = |w|, wn = w . n,
// c_X = 1/2 rho A C_X; drag c_d s wn n, skin friction c_f s (w - wn n), lift
// c_l (wn s n - (wn^2 / s) w).
Vec3 documentedAirForce(const Vec3 (&x)[3], const Vec3 (&v)[3], const AirParams& air) {
    const Vec3 cross = (x[1] - x[0]).cross(x[2] - x[0]);
    const Scalar area = cross.norm() / 2;
    const Vec3 w = air.wind - (v[0] + v[1] + v[2]) / 3;
    const Scalar s = w.norm();
    const Vec3 n = (w.dot(cross) >= 0 ? 1.0 : -1.0) * cross.normalized();
    const Scalar wn = w.dot(n);
    const Scalar halfRhoA = 0.5 * air.density * area;
    const Vec3 drag = halfRhoA * air.dragCoefficient * s * wn * n;
    const Vec3 friction = halfRhoA * air.frictionCoefficient * s * (w - wn * n);
    const Vec3 lift = halfRhoA * air.liftCoefficient * (wn * s * n - (wn * wn / s) * w);
    return drag + friction + lift;
}

// Every corner gets a third of each of its triangles' documented force.
Points documentedAirForces(const Model& model, const State& state, const AirParams& air) {
    Points f = Points::Zero(3, model.particleCount());
    for (const Triangle& t : model.triangles()) {
        const Vec3 x[3] = {state.x.col(t[0]), state.x.col(t[1]), state.x.col(t[2])};
        const Vec3 v[3] = {state.v.col(t[0]), state.v.col(t[1]), state.v.col(t[2])};
        const Vec3 third = documentedAirForce(x, v, air) / 3;
        for (const Index p : t) f.col(p) += third;
    }
    return f;
}

// One triangle, and two sharing an edge (a corner's force then sums two triangles).
std::vector<Model> airModels() {
    Points rest(3, 4);
    rest << 0, 1, 0, 1.2,  //
        0, 0, 1, 0.9,      //
        0, 0, 0, 0.3;
    return {Model::fromMesh(rest.leftCols(3), {{0, 1, 2}}, 0.01, {10, 10, 1}),
            Model::fromMesh(rest, {{0, 1, 2}, {1, 3, 2}}, 0.02, {10, 10, 1})};
}

}  // namespace

// =============================================================================================
// 1. Air

TEST(PhysicsAir, ForcesEqualTheDocumentedPerTriangleFormula) {
    struct Coefficients {
        const char* name;
        Scalar drag, lift, friction;
    };
    // Each term alone (a wrong term is named by the failure), then all together.
    const Coefficients sets[] = {
        {"drag", 1.1, 0, 0}, {"lift", 0, 0.7, 0}, {"friction", 0, 0, 0.3}, {"all", 1.1, 0.7, 0.3}};
    for (const Coefficients& c : sets) {
        Scalar worst = 0;  // the largest relative error over the random cases, and where
        std::string worstCase;
        for (const Model& model : airModels()) {
            const int n = model.particleCount();
            for (unsigned seed = 1; seed <= 20; ++seed) {
                std::mt19937 rng(seed);
                State state = State::atRest(model);
                for (Index i = 0; i < n; ++i) {
                    state.x.col(i) += randomVec(rng, -0.3, 0.3);
                    state.v.col(i) = randomVec(rng, -3, 3);
                }
                AirParams air;
                air.wind = randomVec(rng, -10, 10);
                air.density = 1.25;
                air.dragCoefficient = c.drag;
                air.liftCoefficient = c.lift;
                air.frictionCoefficient = c.friction;
                const Points before = randomPoints(n, 0.01, seed);  // addAirForces adds to f
                Points f = before;
                addAirForces(model, state, air, f);
                const Points expected = documentedAirForces(model, state, air);
                const Scalar error = relativeError(flat(f - before), flat(expected));
                if (error > worst) {
                    worst = error;
                    std::ostringstream where;
                    where << model.triangles().size() << " triangle(s), seed " << seed << ": library force on particle 0 "
                          << (f - before).col(0).transpose() << ", formula of air.h " << expected.col(0).transpose();
                    worstCase = where.str();
                }
            }
        }
        EXPECT_LE(worst, 1e-12) << c.name << " coefficients, worst case " << worstCase;
    }
}

TEST(PhysicsAir, TwoThreadsAndTheForcesAloneGiveTheBitsOfOne) {
    // The forces and their velocity Jacobian on a moving 33 x 33 flag; the formula itself is
    // checked above, on one thread.
    HangingFlag flag = makeHangingFlag(HangingFlagDesc{});
    std::mt19937 rng(4);
    for (Index i = 0; i < flag.model.particleCount(); ++i) {
        flag.state.x.col(i) += randomVec(rng, -0.01, 0.01);
        flag.state.v.col(i) = randomVec(rng, -3, 3);
    }
    AirParams air;
    air.wind = Vec3(6, 1, -2);
    const Points start = randomPoints(flag.model.particleCount(), 0.01, 4);
    Points one = start, split = start;
    std::vector<Mat3> jOne, jSplit;
    ThreadPool two(2);
    addAirForces(flag.model, flag.state, air, one, &jOne);
    addAirForces(flag.model, flag.state, air, split, &jSplit, &two);
    EXPECT_GT((one - start).norm(), 1e-3) << "the air should push the flag";
    EXPECT_TRUE(one == split) << "max |df| " << (one - split).cwiseAbs().maxCoeff();
    for (std::size_t i = 0; i < jOne.size(); ++i) ASSERT_TRUE(jOne[i] == jSplit[i]) << "df/dv of particle " << i;
    // Without the Jacobian, the bits of the forces with it, on one thread and on two.
    Points alone = start, alone2 = start;
    addAirForces(flag.model, flag.state, air, alone);
    addAirForces(flag.model, flag.state, air, alone2, nullptr, &two);
    EXPECT_TRUE(alone == one) << "max |df| " << (alone - one).cwiseAbs().maxCoeff();
    EXPECT_TRUE(alone2 == one) << "max |df| " << (alone2 - one).cwiseAbs().maxCoeff();
}

TEST(PhysicsAir, NoForceWhenTheAirMovesWithTheCloth) {
    for (const Model& model : airModels()) {
        std::mt19937 rng(7);
        State state = State::atRest(model);
        AirParams air;
        air.wind = Vec3(7.3, -0.1, 2.9);
        for (Index i = 0; i < model.particleCount(); ++i) {
            state.x.col(i) += randomVec(rng, -0.3, 0.3);
            state.v.col(i) = air.wind;  // every particle moves with the air
        }
        Points f = Points::Zero(3, model.particleCount());
        std::vector<Mat3> dfdv;
        addAirForces(model, state, air, f, &dfdv);
        EXPECT_LE(f.norm(), 1e-12) << "force on cloth at rest relative to the air:\n" << f;
        // The force is quadratic in w, so its velocity derivative vanishes at w = 0 as well.
        for (std::size_t i = 0; i < dfdv.size(); ++i)
            EXPECT_LE(dfdv[i].norm(), 1e-12) << "df/dv of particle " << i << ":\n" << dfdv[i];
    }
}

// The damping block's closed form (the smallest eigenvalue by Newton's method, then the negative
// part taken off) against Eigen's eigen-decomposition with its eigenvalues clamped, on random
// symmetric matrices of every sign pattern and on repeated eigenvalues. A double root of the
// characteristic polynomial is found to about the square root of the precision (as by Eigen's
// own closed form, computeDirect): the eigenvalue to 1e-6 of the matrix's scale, the block to 1e-7.
TEST(PhysicsAir, TheDampingBlockIsThePositivePartOfAnEigenDecomposition) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<Scalar> u(-1, 1);
    std::vector<Mat3> cases;
    for (int k = 0; k < 4000; ++k) {
        Mat3 q = Eigen::Quaternion<Scalar>(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
        Vec3 lambda(u(rng), u(rng), u(rng));
        if (k % 4 == 1) lambda = lambda.cwiseAbs();          // positive semidefinite
        if (k % 4 == 2) lambda(1) = lambda(0);                // a repeated eigenvalue
        if (k % 4 == 3) lambda *= std::pow(Scalar(10), Scalar(k % 7 - 3));
        cases.push_back(q * lambda.asDiagonal() * q.transpose());
    }
    cases.push_back(Vec3(-1, -1, 2).asDiagonal());
    cases.push_back(Vec3(1, 1, -1).asDiagonal());
    cases.push_back(Vec3(0, 0, -1).asDiagonal());
    cases.push_back(Mat3::Zero());
    for (const Mat3& sym : cases) {
        Eigen::SelfAdjointEigenSolver<Mat3> eig(sym);
        const Mat3 expected = eig.eigenvectors() * eig.eigenvalues().cwiseMax(Scalar(0)).asDiagonal() *
                              eig.eigenvectors().transpose();
        const Scalar scale = std::max(sym.cwiseAbs().maxCoeff(), Scalar(1e-300));
        // dampingBlock takes dfdv: the symmetric part of -dfdv is sym.
        const Mat3 got = dampingBlock(-sym);
        ASSERT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-7 * scale) << sym;
        ASSERT_NEAR(smallestEigenvalue(sym), eig.eigenvalues()(0), 1e-6 * scale) << sym;
        const Scalar smallestOfGot = Eigen::SelfAdjointEigenSolver<Mat3>(got).eigenvalues()(0);
        ASSERT_GE(smallestOfGot, -1e-7 * scale) << "not positive semidefinite:\n" << got;
    }
}
