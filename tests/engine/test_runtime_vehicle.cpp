// The vehicle scenes through the runtime: pins on a driven path, a trailing flag, Bullet only
// where declared. Rendering is switched off here (see test_runtime_render.cpp for frames).

#include <gtest/gtest.h>

#include "engine/runtime.h"
#include "headless_scene.h"

using namespace engine;

TEST(RuntimeVehicle, ThePolesNeighboursFollowItAlongTheDrivenPath) {
    // The pins' targets lie on one vertical line of the pole, a row spacing apart, and every
    // pinned particle's free neighbour stays within a stretched spring of its pin, while the
    // vehicle drives the slalom and brakes hard. (Where the pinned particles themselves end up
    // cannot fail a test: the step assigns them their targets.)
    const SceneConfig scene = headlessScene("flag_vehicle");
    RunOptions o;
    o.duration = 6;  // accelerate, slalom, into the hard brake
    Runtime rt(scene, o);
    const int nx = scene.flag.nx;
    const double dx = scene.flag.width / (nx - 1), dy = scene.flag.height / (scene.flag.ny - 1);
    double maxSpeed = 0, maxSpacingError = 0, maxNeighbourDistance = 0;
    while (rt.frame()) {
        maxSpeed = std::max(maxSpeed, rt.carrierVelocity().norm());
        const auto& pins = rt.flag()->pins();
        const Eigen::Vector3d down = (pins.back().x - pins.front().x).normalized();
        for (std::size_t r = 0; r < pins.size(); ++r) {
            const Eigen::Vector3d expected = pins.front().x + double(r) * dy * down;
            maxSpacingError = std::max(maxSpacingError, (pins[r].x - expected).norm());
            maxNeighbourDistance =
                std::max(maxNeighbourDistance, (rt.flag()->state().x.col(pins[r].particle + 1) - pins[r].x).norm());
        }
    }
    EXPECT_GT(maxSpeed, 10.0) << "the script should really drive";
    EXPECT_LT(maxSpacingError, 1e-9);
    EXPECT_LT(maxNeighbourDistance, 1.5 * dx);
    EXPECT_EQ(rt.flag()->failures(), 0);
}

TEST(RuntimeVehicle, FlagTrailsBehindAtSpeedAndHangsAtRest) {
    SceneConfig s = headlessScene("flag_vehicle");
    s.script = std::string(FLAGSIM_ASSETS_DIR) + "/scripts/cruise.json";
    RunOptions o;
    o.duration = 7;
    Runtime rt(s, o);
    int checked = 0;
    while (rt.frame()) {
        const Eigen::Vector3d v = rt.carrierVelocity();
        if (rt.simTime() < 4.0 || v.norm() < 5.0) continue;
        // Behind the pole against the direction of travel, by a good part of the flag's width.
        const Eigen::Vector3d centroid = rt.flag()->state().x.rowwise().mean();
        const double along = (centroid - rt.poleTop()).dot(v.normalized());
        EXPECT_LT(along, -0.4 * s.flag.width) << "t = " << rt.simTime() << ", speed " << v.norm();
        ++checked;
    }
    EXPECT_GT(checked, 60) << "the cruise never held above 5 m/s";

    // At rest in still air: hangs below the pole top. Released flat with its top edge at the pole
    // top, a flag that only loses energy to the air does not climb back over the pole top once the
    // vehicle has settled on its wheels (1.5 s; the paper's step with 3 anti-stretch passes and
    // tethers at 1% threw it 0.3 m above it, and about half the configurations of
    // docs/study/rest_climb.csv rise over it).
    SceneConfig still = headlessScene("flag_vehicle");
    still.script.clear();
    RunOptions o2;
    o2.duration = 5;
    Runtime rest(still, o2);
    double highest = -1e9;
    while (rest.frame())
        if (rest.simTime() >= 1.5)
            highest = std::max(highest, rest.flag()->state().x.row(1).maxCoeff() - rest.poleTop().y());
    const Eigen::Vector3d centroid = rest.flag()->state().x.rowwise().mean();
    EXPECT_LT(rest.carrierVelocity().norm(), 0.05);
    EXPECT_LT(centroid.y(), rest.poleTop().y() - 0.6 * still.flag.height);
    EXPECT_LT(highest, 0.02) << "m above the pole top";
}

TEST(RuntimeVehicle, VehicleOnlySceneHasNoClothPhases) {
    RunOptions o;
    o.frames = 10;
    const SubsystemCounters before = subsystemCounters();
    Runtime rt(headlessScene("vehicle_only"), o);
    while (rt.frame()) {
    }
    EXPECT_EQ(rt.flag(), nullptr);
    for (const std::string& p : rt.profiler().phases())
        EXPECT_TRUE(p == "input" || p == "bullet" || p.rfind("bullet:", 0) == 0) << p;
    EXPECT_EQ(subsystemCounters().bulletWorlds, before.bulletWorlds + 1);
    EXPECT_EQ(subsystemCounters().glContexts, before.glContexts);
}
