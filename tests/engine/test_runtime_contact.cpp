// The main demo's flag (flag_vehicle, with contact) against the same flag without it
// (flag_vehicle_no_contact), on the demo's drive, judged by the library's crossing checker
// (cloth/crossings.h), which shares no code with the contact stage.

#include <gtest/gtest.h>

#include "engine/runtime.h"
#include "headless_scene.h"

using namespace engine;

namespace {

// The most crossings of each kind in one count (after each frame's ticks) over the first `frames`
// (all of the drive: 600).
cloth::CrossingCounts mostCrossings(const SceneConfig& scene, int frames) {
    RunOptions o;
    o.frames = frames;
    Runtime rt(scene, o);
    while (rt.frame()) {
    }
    return rt.mostCrossings();
}

}  // namespace

TEST(RuntimeContact, TheDemoFlagWithContactNeverPassesThroughItselfWhereWithoutItDoes) {
    const SceneConfig a = headlessScene("flag_vehicle_no_contact"), b = headlessScene("flag_vehicle");
    EXPECT_FALSE(a.flag.contact.enabled);
    EXPECT_TRUE(b.flag.contact.enabled);
    EXPECT_TRUE(b.flag.contact.self);
    EXPECT_GT(mostCrossings(a, 150).selfEdges, 0);  // the case is hard: the paper's step folds through itself
    EXPECT_EQ(mostCrossings(b, 150).selfEdges, 0);
}

TEST(RuntimeContact, TheMainDemoCrossesNothingOnTheWholeDriveWhereWithoutContactItCrossesItsPole) {
    // Without contact the demo's flag takes edges through its pole in the last turn.
    const cloth::CrossingCounts bare = mostCrossings(headlessScene("flag_vehicle_no_contact"), 600);
    EXPECT_GT(bare.poleEdges, 0);
    const cloth::CrossingCounts demo = mostCrossings(headlessScene("flag_vehicle"), 600);
    EXPECT_EQ(demo.total(), 0) << demo.poleEdges << " pole, " << demo.selfEdges << " self, " << demo.bodyEdges
                               << " body edges, " << demo.groundParticles << " particles below the ground";
}
