// The main demo's flag (flag_vehicle, without contact) against the same flag with contact: with the
// pole and the vehicle's body alone, and with itself too (flag_vehicle_contact), on the demo's
// drive, judged by the library's crossing checker (cloth/crossings.h), which shares no code with the
// contact stage.

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

SceneConfig withSolidsOnly(SceneConfig s) {  // contact with the pole and the body, not with itself
    s.flag.contact.enabled = true, s.flag.contact.self = false;
    return s;
}

}  // namespace

TEST(RuntimeContact, TheDemoFlagWithContactNeverPassesThroughItselfWhereWithoutItDoes) {
    const SceneConfig a = headlessScene("flag_vehicle"), b = headlessScene("flag_vehicle_contact");
    EXPECT_FALSE(a.flag.contact.enabled);
    EXPECT_TRUE(b.flag.contact.enabled);
    EXPECT_TRUE(b.flag.contact.self);
    EXPECT_GT(mostCrossings(a, 150).selfEdges, 0);  // the case is hard: the paper's step folds through itself
    EXPECT_EQ(mostCrossings(b, 150).selfEdges, 0);
}

TEST(RuntimeContact, ContactWithThePoleKeepsThePapersStepOutOfItOnTheWholeDrive) {
    // Without contact the demo's flag takes edges through its pole in the last turn (21 at once).
    const SceneConfig demo = headlessScene("flag_vehicle");
    EXPECT_GT(mostCrossings(demo, 600).poleEdges, 0);
    EXPECT_EQ(mostCrossings(withSolidsOnly(demo), 600).poleEdges, 0);
}
