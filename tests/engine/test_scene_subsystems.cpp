// Each shipped scene builds only what it declares: its profile has exactly the phases of its
// declared subsystems, and Bullet worlds / GL contexts exist only where declared.

#include <gtest/gtest.h>

#include "engine/runtime.h"

using namespace engine;

namespace {

// The phases a subsystem set must produce, written out here independently of the runtime.
std::vector<std::string> expectedPhases(unsigned s, bool contact) {
    std::vector<std::string> p;
    if (s & kVehicle) p.insert(p.end(), {"input", "bullet"});
    if (s & kCloth) {
        if (s & kAir) p.push_back("air");
        p.insert(p.end(), {"cloth_forces", "cloth_solve"});
        if (s & kCollision) p.push_back("collision");
        if ((s & kCollision) && contact) p.push_back("contact");
        if (s & kCollision) p.push_back("crossings");
    }
    // The software rasterizer the tests run on gets the post pass (render.aa = auto).
    if (s & kRender) p.insert(p.end(), {"render", "readback", "aa"});
    if (s & kRecording) p.push_back("write");
    return p;
}

}  // namespace

TEST(SceneSubsystems, EveryShippedSceneProfilesExactlyItsDeclaredPhases) {
    for (const char* name : {"flag_vehicle", "flag_vehicle_stiff", "flag_vehicle_true_motion", "flag_vehicle_no_contact", "hanging_flag",
                             "bench_cloth", "vehicle_only"}) {
        SceneConfig s = loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/" + name + ".json");
        s.render.width = 160;
        s.render.height = 90;
        s.render.shadowMapSize = 256;
        RunOptions o;
        o.frames = 5;  // no --out: the recording subsystem is off for this run
        const unsigned declared = s.subsystems & ~kRecording;
        const SubsystemCounters before = subsystemCounters();
        Runtime rt(s, o);
        while (rt.frame()) {
        }
        std::vector<std::string> phases;
        for (const std::string& p : rt.profiler().phases())
            if (p.rfind("bullet:", 0) != 0) phases.push_back(p);
            else EXPECT_TRUE(declared & kVehicle) << name << ": Bullet zone " << p << " without a vehicle";
        EXPECT_EQ(phases, expectedPhases(declared, s.flag.contact.enabled)) << name;
        const SubsystemCounters after = subsystemCounters();
        EXPECT_EQ(after.bulletWorlds - before.bulletWorlds, (declared & kVehicle) ? 1 : 0) << name;
        EXPECT_EQ(after.glContexts - before.glContexts, (declared & kRender) ? 1 : 0) << name;
        EXPECT_EQ(after.windows, before.windows) << name;
        EXPECT_EQ(rt.flag() != nullptr, bool(declared & kCloth)) << name;
        if (rt.flag()) {
            EXPECT_EQ(rt.flag()->failures(), 0) << name << ": " << rt.flag()->firstFailure();
        }
    }
}
