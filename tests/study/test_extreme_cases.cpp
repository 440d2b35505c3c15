// The study's extreme cases (tools/study/cpp/extreme_cases.h): every case drives the demo's flag, and
// the guard that says so rejects a case that moves nothing.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "extreme_cases.h"

using engine::RigidFrame;
using Eigen::Vector3d;

namespace {

engine::SceneConfig demoScene() {  // as the study takes it: without contact
    return study::withContact(engine::loadScene(engine::resolveScenePath("flag_vehicle", FLAGSIM_ASSETS_DIR)), false);
}

study::Extreme caseNamed(const std::string& name) {
    for (const study::Extreme& x : study::extremes())
        if (x.name == name) return x;
    ADD_FAILURE() << "no extreme case " << name;
    return {};
}

}  // namespace

TEST(ExtremeCases, EveryShippedCaseMovesThePinsOrHasWind) {
    const std::vector<study::CaseMotion> motions = study::caseMotions(demoScene(), study::extremes());
    ASSERT_EQ(motions.size(), 6u);
    for (const study::CaseMotion& c : motions) EXPECT_TRUE(c.drivesTheFlag()) << c.name;
    EXPECT_EQ(study::idleCases(motions), "");
    // The turn: every pin circles the axis 1.6 m away, at 5 * 1.6 = 8 m/s once the turn is up to
    // speed, with a centripetal 5^2 * 1.6 = 40 m/s^2 (and 10 * 1.6 = 16 m/s^2 along the path while
    // the rate ramps up, sqrt(40^2 + 16^2) = 43.1 m/s^2 at the end of the ramp).
    const study::CaseMotion& spin = motions[2];
    ASSERT_EQ(spin.name, "spin_5radps");
    EXPECT_NEAR(spin.pins.speedMax, 8.0, 1e-9);
    EXPECT_GT(spin.pins.accelMax, 40.0);
    EXPECT_LT(spin.pins.accelMax, 43.2);
    EXPECT_EQ(spin.wind, 0.0);
}

TEST(ExtremeCases, TheSpinAboutThePolesOwnAxisFailsTheGuard) {
    // The spin as it was: the carrier turned about the vertical through its origin, where the
    // pole stands. The pinned column lies on that axis, so no pin moves: the guard must say so.
    const study::Extreme shipped = caseNamed("spin_5radps");
    const auto aboutThePole = [](double t) {
        RigidFrame c;
        const double w = 5 * std::min(t / 0.5, 1.0);
        const double angle = t < 0.5 ? 5 * t * t : 1.25 + 5 * (t - 0.5);
        c.rotation = Eigen::AngleAxisd(angle, Vector3d::UnitY());
        c.angularVelocity = Vector3d(0, w, 0);
        return c;
    };
    const engine::SceneConfig demo = demoScene();
    study::Extreme old = shipped;
    old.carrier = aboutThePole;
    const std::vector<study::CaseMotion> motions = study::caseMotions(demo, {old, shipped});
    EXPECT_LT(motions[0].pins.speedMax, study::kIdleSpeed);
    EXPECT_LT(motions[0].pins.accelMax, study::kIdleAccel);
    EXPECT_FALSE(motions[0].drivesTheFlag());
    EXPECT_TRUE(motions[1].drivesTheFlag());
    EXPECT_NE(study::idleCases(motions).find("'spin_5radps' moves no pin"), std::string::npos)
        << study::idleCases(motions);
    // Wind alone drives the flag: the same idle carrier with wind passes.
    study::CaseMotion windy = motions[0];
    windy.wind = 40;
    EXPECT_TRUE(windy.drivesTheFlag());
}

TEST(ExtremeCases, TheSpinTurnsAboutTheDemoChassisOriginOneAndAHalfMetresFromThePole) {
    // The pinned column stands on the pole's axis (carrier x = z = 0); the spin's axis is where
    // the demo's chassis origin is relative to its pole, at least 1 m from it.
    const engine::SceneConfig demo = demoScene();
    const std::vector<Vector3d> pins = study::pinnedColumn(demo, study::extremeMount(demo));
    ASSERT_EQ(int(pins.size()), demo.flag.ny);
    for (const Vector3d& p : pins) EXPECT_EQ(std::hypot(p.x(), p.z()), 0.0);
    const double axisDistance = std::hypot(study::kSpinAxisPoint.x(), study::kSpinAxisPoint.z());
    EXPECT_GE(axisDistance, 1.0);
    EXPECT_DOUBLE_EQ(axisDistance, std::hypot(demo.vehicle.poleOffset[0], demo.vehicle.poleOffset[2]));
    // The carrier's velocity is the derivative of its pose, and the axis stays put.
    const study::Extreme spin = caseNamed("spin_5radps");
    for (double t : {0.1, 0.3, 0.7, 2.0}) {
        const double e = 1e-6;
        const RigidFrame c = spin.carrier(t), before = spin.carrier(t - e), after = spin.carrier(t + e);
        EXPECT_LT((c.linearVelocity - (after.position - before.position) / (2 * e)).norm(), 1e-6) << "t " << t;
        EXPECT_LT((c.point(study::kSpinAxisPoint) - study::kSpinAxisPoint).norm(), 1e-12) << "t " << t;
    }
}

// The teleports of other lengths (cloth_study --teleports): named by their length, the pole still
// until 0.5 s and then that far along +x, without a velocity; the shipped 1 m case is one of them.
TEST(ExtremeCases, ATeleportOfAnyLengthJumpsThatFarAtHalfASecond) {
    const study::Extreme t = study::teleport(0.85);
    EXPECT_EQ(t.name, "teleport_0.85m");
    EXPECT_EQ(study::teleportName(1.25), "teleport_1.25m");
    EXPECT_EQ(t.jumpAt, 0.5);
    EXPECT_EQ(t.carrier(0.5 - 1.0 / 240).position, Vector3d::Zero());
    EXPECT_EQ(t.carrier(0.5).position, Vector3d(0.85, 0, 0));
    EXPECT_EQ(t.carrier(1.7).linearVelocity, Vector3d::Zero());
    const study::Extreme one = caseNamed("teleport_1m");
    EXPECT_EQ(one.carrier(0.49).position, Vector3d::Zero());
    EXPECT_EQ(one.carrier(0.5).position, Vector3d(1, 0, 0));
    EXPECT_EQ(one.duration, t.duration);
}
