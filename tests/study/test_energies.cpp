// The study's flutter energies (tools/study/cpp/extreme_runs.h) against closed forms: a flag moving
// with its carrier has none; one translating at u relative to it has M |u|^2 / 2 in both the
// whole and the patch energy; one whose columns carry momentum +m u and -m u in turn
// (grid-scale motion) has sum m^2 |u|^2 / 2 m_i in the whole energy and none at the patches' scale;
// one whose halves move at +u and -u has M |u|^2 / 2 in both. Each at every patch count the study
// writes.

#include <gtest/gtest.h>

#include <cmath>

#include "extreme_runs.h"

namespace {

cloth::Model grid(int n) {  // n x n particles, 2 x 2 per patch when n = 2 patches
    cloth::GridDesc d;
    d.nx = d.ny = n;
    d.totalMass = 0.25;
    return cloth::Model::fromGrid(d);
}

// An n x n grid at rest in a spinning carrier's frame: every particle at the carrier's velocity.
struct Carried {
    cloth::Model m;
    engine::RigidFrame c;
    cloth::State s;
};

Carried carried(int n) {
    Carried f{grid(n), {}, {}};
    f.c.position = Eigen::Vector3d(0.3, -0.2, 0.1);
    f.c.linearVelocity = Eigen::Vector3d(20, 0, -3);
    f.c.angularVelocity = Eigen::Vector3d(0, 5, 1);
    f.s = {f.m.restPositions(), cloth::Points::Zero(3, f.m.particleCount())};
    for (cloth::Index i = 0; i < f.m.particleCount(); ++i) f.s.v.col(i) = f.c.velocityAt(f.s.x.col(i));
    return f;
}

}  // namespace

TEST(FlutterEnergy, IsZeroForAFlagMovingWithItsCarrier) {
    for (int patches : study::kPatchCounts) {
        const Carried f = carried(2 * patches);
        EXPECT_NEAR(study::carrierEnergy(f.m, f.s, f.c), 0.0, 1e-20);
        EXPECT_NEAR(study::patchEnergy(f.m, f.s, f.c, patches), 0.0, 1e-20) << patches;
    }
}

TEST(FlutterEnergy, ATranslationCountsWholeAtEveryScale) {
    Carried f = carried(33);
    const Eigen::Vector3d u(1.5, -2.0, 0.5);
    for (cloth::Index i = 0; i < f.m.particleCount(); ++i) f.s.v.col(i) += u;
    const double expected = 0.5 * 0.25 * u.squaredNorm();
    EXPECT_NEAR(study::carrierEnergy(f.m, f.s, f.c), expected, 1e-12);
    for (int patches : study::kPatchCounts) EXPECT_NEAR(study::patchEnergy(f.m, f.s, f.c, patches), expected, 1e-12) << patches;
}

TEST(FlutterEnergy, MotionAtTheScaleOfPatchesCountsWhole) {
    // The flag's two halves move at +u and -u: every patch moves as one, so the patch energy is
    // the whole M |u|^2 / 2, while the flag's mean momentum is zero.
    for (int patches : study::kPatchCounts) {
        const int n = 2 * patches;
        Carried f = carried(n);
        const Eigen::Vector3d u(0, 0, 3);
        for (cloth::Index i = 0; i < f.m.particleCount(); ++i) f.s.v.col(i) += (i % n) < n / 2 ? u : Eigen::Vector3d(-u);
        EXPECT_NEAR(study::carrierEnergy(f.m, f.s, f.c), 0.5 * 0.25 * u.squaredNorm(), 1e-12);
        EXPECT_NEAR(study::patchEnergy(f.m, f.s, f.c, patches), 0.5 * 0.25 * u.squaredNorm(), 1e-12) << patches;
    }
}

TEST(FlutterEnergy, GridScaleMotionHasNoPatchEnergy) {
    // Columns alternate momentum +m u and -m u (m: the mean particle mass; the lumped masses
    // differ at the edges), so every 2 x 2 patch's momentum cancels.
    for (int patches : study::kPatchCounts) {
        const int n = 2 * patches;
        Carried f = carried(n);
        const Eigen::Vector3d u(0, 0, 3);
        const double mean = 0.25 / f.m.particleCount();
        double expected = 0;
        for (cloth::Index i = 0; i < f.m.particleCount(); ++i) {
            const double mi = f.m.masses()[i];
            f.s.v.col(i) += ((i % n) % 2 == 0 ? 1.0 : -1.0) * mean / mi * u;
            expected += 0.5 * mean * mean / mi * u.squaredNorm();
        }
        EXPECT_NEAR(study::carrierEnergy(f.m, f.s, f.c), expected, 1e-12 * expected);
        EXPECT_LT(study::patchEnergy(f.m, f.s, f.c, patches), 1e-12 * expected) << patches;
    }
}

TEST(FlutterEnergy, IsNotDefinedOnAGridCoarserThanItsPatches) {
    for (int patches : study::kPatchCounts) {
        const Carried f = carried(patches - 1);
        EXPECT_TRUE(std::isnan(study::patchEnergy(f.m, f.s, f.c, patches))) << patches;
    }
}
