// The runtime on cloth-only scenes: only declared subsystems are built and profiled.

#include <gtest/gtest.h>

#include <cstring>

#include "engine/runtime.h"

using namespace engine;

namespace {

SceneConfig scene(const char* name) {
    return loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/" + name + ".json");
}

}  // namespace

TEST(RuntimeCloth, BenchClothHasExactlyItsPhasesAndNoBulletWorldOrGlContext) {
    const SubsystemCounters before = subsystemCounters();
    RunOptions o;
    o.frames = 30;
    Runtime rt(scene("bench_cloth"), o);
    while (rt.frame()) {
    }
    EXPECT_EQ(rt.profiler().phases(), (std::vector<std::string>{"air", "cloth_forces", "cloth_solve"}));
    EXPECT_EQ(rt.profiler().frameCount(), 30u);
    const SubsystemCounters after = subsystemCounters();
    EXPECT_EQ(after.bulletWorlds, before.bulletWorlds);
    EXPECT_EQ(after.glContexts, before.glContexts);
    EXPECT_EQ(after.windows, before.windows);
    ASSERT_NE(rt.flag(), nullptr);
    EXPECT_EQ(rt.flag()->steps(), 30 * 4);  // 240 Hz ticks at 60 frames/s
}

TEST(RuntimeCloth, SameSceneGivesBitIdenticalClothState) {
    std::vector<double> runs[2];
    for (auto& out : runs) {
        RunOptions o;
        o.frames = 60;
        Runtime rt(scene("bench_cloth"), o);
        while (rt.frame()) {
        }
        const auto& x = rt.flag()->state().x;
        out.assign(x.data(), x.data() + x.size());
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    EXPECT_EQ(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(double)), 0);
}
