// The flag subsystem without Bullet: a carrier frame moved by hand.

#include <gtest/gtest.h>

#include "cloth/diagnostics.h"
#include "engine/flag/flag.h"

using namespace engine;

namespace {

SceneConfig flagScene(unsigned subsystems) {
    SceneConfig s;
    s.file = "(test)";
    s.subsystems = subsystems;
    s.flag.nx = 17;
    s.flag.ny = 12;
    return s;
}

Eigen::Vector3d centroid(const cloth::State& st) { return st.x.rowwise().mean(); }

}  // namespace

TEST(Flag, PinsMapTheFlagsPoleEdgeToThePoleAndTheirNeighboursFollow) {
    // What the pins do, checked from outside the flag: (1) the pinned particles are the flag's
    // pole edge, column 0 of its row-major grid, top to bottom; (2) each pin's target is the pole
    // point of its row, computed here from the mount and the carrier; (3) the free neighbour of
    // each pinned particle (column 1) is carried along: it stays within a stretched spring of
    // its pin while the carrier accelerates at 8 m/s^2 and turns. (Where pinned particles end
    // up cannot fail a test: the step assigns them their targets.)
    const SceneConfig scene = flagScene(kCloth | kAir | kCollision);
    PoleMount mount;
    mount.base = Eigen::Vector3d(0, 0.5, -1.5);
    mount.height = 2.5;
    RigidFrame carrier;
    Flag flag(scene, mount, carrier);
    const int nx = scene.flag.nx, ny = scene.flag.ny;
    ASSERT_EQ(int(flag.pins().size()), ny);
    for (int r = 0; r < ny; ++r) EXPECT_EQ(flag.pins()[r].particle, r * nx) << "row " << r;
    const double dx = scene.flag.width / (nx - 1), dy = scene.flag.height / (ny - 1), h = 1.0 / 240;
    double maxTargetError = 0, maxNeighbourDistance = 0;
    for (int k = 1; k <= 720; ++k) {  // 3 s: accelerate, turn, bounce
        const double t = k * h;
        carrier.position = Eigen::Vector3d(2 * std::sin(t), 0.1 * std::sin(9 * t), 4 * t * t);
        carrier.linearVelocity = Eigen::Vector3d(2 * std::cos(t), 0.9 * std::cos(9 * t), 8 * t);
        carrier.rotation = Eigen::AngleAxisd(0.5 * t, Eigen::Vector3d::UnitY());
        carrier.angularVelocity = Eigen::Vector3d(0, 0.5, 0);
        flag.tick(h, carrier, {flag.poleCollider(carrier)});
        for (int r = 0; r < ny; ++r) {
            const Eigen::Vector3d local = mount.base + Eigen::Vector3d(0, mount.height - r * dy, 0);
            const Eigen::Vector3d pole = carrier.rotation * local + carrier.position;
            maxTargetError = std::max(maxTargetError, (flag.pins()[r].x - pole).norm());
            maxNeighbourDistance = std::max(maxNeighbourDistance, (flag.state().x.col(r * nx + 1) - pole).norm());
        }
    }
    EXPECT_LT(maxTargetError, 1e-12);
    EXPECT_LT(maxNeighbourDistance, 1.5 * dx);
    EXPECT_EQ(flag.failures(), 0);
}

TEST(Flag, TrailsBehindAMovingCarrierAndHangsInStillAir) {
    const SceneConfig scene = flagScene(kCloth | kAir);
    PoleMount mount;
    mount.height = 3;
    const double h = 1.0 / 240;
    {   // At rest in still air: hangs below the pole top.
        RigidFrame carrier;
        Flag flag(scene, mount, carrier);
        for (int k = 0; k < 4 * 240; ++k) flag.tick(h, carrier, {});
        const Eigen::Vector3d c = centroid(flag.state());
        EXPECT_LT(c.y(), mount.height - 0.6 * scene.flag.height);
        // and close to the pole: hanging, not streaming
        EXPECT_LT(std::hypot(c.x(), c.z()), 0.5 * scene.flag.width);
    }
    {   // Moving at 10 m/s along +x (the flag set up trailing sideways, along -z): it swings
        // round to trail behind, against the direction of travel.
        RigidFrame carrier;
        carrier.linearVelocity = Eigen::Vector3d(10, 0, 0);
        Flag flag(scene, mount, carrier);
        for (int k = 1; k <= 4 * 240; ++k) {
            carrier.position = carrier.linearVelocity * (k * h);
            flag.tick(h, carrier, {});
        }
        const Eigen::Vector3d rel = centroid(flag.state()) - carrier.position;
        EXPECT_LT(rel.x(), -0.3 * scene.flag.width) << rel.transpose();
        EXPECT_GT(rel.y(), mount.height - 0.8 * scene.flag.height) << "streams, does not hang";
    }
}

TEST(Flag, ThePoleDoesNotPushTheSleeveOutOfItself) {
    // A 65x65 flag's second column rests 2.3 cm from the pole's axis, inside its collision capsule
    // (3 cm radius + 1.5 cm thickness). A flag hanging from a still pole never touches the pole, so
    // with the pole collider on it must hang as it does with collisions off; the collider used to
    // push that column out every tick and held its springs at 92% stretch.
    SceneConfig scene = flagScene(kCloth);
    scene.flag.nx = scene.flag.ny = 65;
    PoleMount mount;
    mount.height = 3;
    RigidFrame carrier;
    const double h = 1.0 / 240;
    auto hang = [&](bool collide) {
        SceneConfig s = scene;
        if (collide) s.subsystems |= kCollision;
        Flag flag(s, mount, carrier);
        for (int k = 0; k < 60; ++k) flag.tick(h, carrier, {flag.poleCollider(carrier)});
        return cloth::measure(flag.model(), {}, flag.state(), true).maxStretch;
    };
    const double free = hang(false), collided = hang(true);
    EXPECT_LT(free, 0.05);
    EXPECT_NEAR(collided, free, 0.01);
}

TEST(Flag, InjectedNaNIsCaughtReportedAndRecovered) {
    const SceneConfig scene = flagScene(kCloth);
    RigidFrame carrier;
    Flag flag(scene, PoleMount{}, carrier);
    for (int k = 0; k < 10; ++k) flag.tick(1.0 / 240, carrier, {});
    flag.mutableState().v(1, 40) = std::numeric_limits<double>::quiet_NaN();
    flag.tick(1.0 / 240, carrier, {});
    EXPECT_GE(flag.failures(), 1);
    EXPECT_NE(flag.firstFailure().find("particle 40"), std::string::npos) << flag.firstFailure();
    EXPECT_NE(flag.firstFailure().find("step 11"), std::string::npos) << flag.firstFailure();
    EXPECT_TRUE(flag.state().x.allFinite() && flag.state().v.allFinite());
}

TEST(Flag, ARunawayParticleIsCaughtAsDivergedAndTheFlagRestarts) {
    // Finite but a kilometre from the pole: no solver calls that non-finite, and the flag must not
    // go on drawing it; the tick's retry (8x the substeps) starts from the same runaway, so the
    // flag goes back to rest on the pole.
    const SceneConfig scene = flagScene(kCloth);
    RigidFrame carrier;
    Flag flag(scene, PoleMount{}, carrier);
    for (int k = 0; k < 10; ++k) flag.tick(1.0 / 240, carrier, {});
    flag.mutableState().x(0, 40) += 1000;
    flag.tick(1.0 / 240, carrier, {});
    EXPECT_EQ(flag.failures(), 2);
    EXPECT_NE(flag.firstFailure().find("step 11: diverged"), std::string::npos) << flag.firstFailure();
    const double diagonal = std::hypot(scene.flag.width, scene.flag.height);
    for (cloth::Index i = 0; i < flag.state().x.cols(); ++i)
        ASSERT_LT((flag.state().x.col(i) - flag.pins().front().x).norm(), 1.01 * diagonal) << i;
}
