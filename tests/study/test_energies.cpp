// The study's flutter energies (tools/study/extreme_runs.h) against closed forms: a flag moving
// with its carrier has none; one translating at u relative to it has M |u|^2 / 2 in both the
// whole and the patch energy; one whose columns carry momentum +m u and -m u in turn
// (grid-scale motion) has sum m^2 |u|^2 / 2 m_i in the whole energy and none at the patches' scale;
// one whose halves move at +u and -u has M |u|^2 / 2 in both.

#include <gtest/gtest.h>

#include <cmath>

#include "extreme_runs.h"

namespace {

cloth::Model grid(int n) {  // n x n particles, 2 x 2 per patch when n = 2 kPatches
    cloth::GridDesc d;
    d.nx = d.ny = n;
    d.totalMass = 0.25;
    return cloth::Model::fromGrid(d);
}

engine::RigidFrame spinningCarrier() {
    engine::RigidFrame c;
    c.position = Eigen::Vector3d(0.3, -0.2, 0.1);
    c.linearVelocity = Eigen::Vector3d(20, 0, -3);
    c.angularVelocity = Eigen::Vector3d(0, 5, 1);
    return c;
}

cloth::State withCarrier(const cloth::Model& m, const engine::RigidFrame& c) {
    cloth::State s{m.restPositions(), cloth::Points::Zero(3, m.particleCount())};
    for (cloth::Index i = 0; i < m.particleCount(); ++i) s.v.col(i) = c.velocityAt(s.x.col(i));
    return s;
}

}  // namespace

TEST(FlutterEnergy, IsZeroForAFlagMovingWithItsCarrier) {
    const cloth::Model m = grid(2 * study::kPatches);
    const engine::RigidFrame c = spinningCarrier();
    const cloth::State s = withCarrier(m, c);
    EXPECT_NEAR(study::carrierEnergy(m, s, c), 0.0, 1e-20);
    EXPECT_NEAR(study::patchEnergy(m, s, c), 0.0, 1e-20);
}

TEST(FlutterEnergy, ATranslationCountsWholeAtEveryScale) {
    const cloth::Model m = grid(33);
    const engine::RigidFrame c = spinningCarrier();
    cloth::State s = withCarrier(m, c);
    const Eigen::Vector3d u(1.5, -2.0, 0.5);
    for (cloth::Index i = 0; i < m.particleCount(); ++i) s.v.col(i) += u;
    const double expected = 0.5 * 0.25 * u.squaredNorm();
    EXPECT_NEAR(study::carrierEnergy(m, s, c), expected, 1e-12);
    EXPECT_NEAR(study::patchEnergy(m, s, c), expected, 1e-12);
}

TEST(FlutterEnergy, MotionAtTheScaleOfPatchesCountsWhole) {
    // The flag's two halves move at +u and -u: every patch moves as one, so the patch energy is
    // the whole M |u|^2 / 2, while the flag's mean momentum is zero.
    const int n = 2 * study::kPatches;
    const cloth::Model m = grid(n);
    const engine::RigidFrame c = spinningCarrier();
    cloth::State s = withCarrier(m, c);
    const Eigen::Vector3d u(0, 0, 3);
    for (cloth::Index i = 0; i < m.particleCount(); ++i) s.v.col(i) += (i % n) < n / 2 ? u : Eigen::Vector3d(-u);
    EXPECT_NEAR(study::carrierEnergy(m, s, c), 0.5 * 0.25 * u.squaredNorm(), 1e-12);
    EXPECT_NEAR(study::patchEnergy(m, s, c), 0.5 * 0.25 * u.squaredNorm(), 1e-12);
}

TEST(FlutterEnergy, GridScaleMotionHasNoPatchEnergy) {
    const int n = 2 * study::kPatches;
    const cloth::Model m = grid(n);
    const engine::RigidFrame c = spinningCarrier();
    cloth::State s = withCarrier(m, c);
    const Eigen::Vector3d u(0, 0, 3);
    // Columns alternate momentum +m u and -m u (m: the mean particle mass; the lumped masses
    // differ at the edges), so every 2 x 2 patch's momentum cancels.
    const double mean = 0.25 / m.particleCount();
    double expected = 0;
    for (cloth::Index i = 0; i < m.particleCount(); ++i) {
        const double mi = m.masses()[i];
        s.v.col(i) += ((i % n) % 2 == 0 ? 1.0 : -1.0) * mean / mi * u;
        expected += 0.5 * mean * mean / mi * u.squaredNorm();
    }
    EXPECT_NEAR(study::carrierEnergy(m, s, c), expected, 1e-12 * expected);
    EXPECT_LT(study::patchEnergy(m, s, c), 1e-12 * expected);
}

TEST(FlutterEnergy, IsNotDefinedOnAGridCoarserThanItsPatches) {
    const cloth::Model m = grid(study::kPatches - 1);
    const cloth::State s = withCarrier(m, engine::RigidFrame{});
    EXPECT_TRUE(std::isnan(study::patchEnergy(m, s, engine::RigidFrame{})));
}
