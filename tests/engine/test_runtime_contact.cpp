// The main demo's flag with contact (flag_vehicle_contact) against the same flag without it, on the
// first 2.5 s of the demo's drive, judged by the library's crossing checker (cloth/crossings.h),
// which shares no code with the contact stage.

#include <gtest/gtest.h>

#include "cloth/crossings.h"
#include "engine/runtime.h"
#include "headless_scene.h"

using namespace engine;

namespace {

// The most self crossings (edge through a triangle at least three cells away) after any frame.
int mostSelfCrossings(const char* scene, int frames) {
    RunOptions o;
    o.frames = frames;
    Runtime rt(headlessScene(scene), o);
    int most = 0;
    while (rt.frame()) {
        const cloth::CrossingCounts c = cloth::countCrossings(rt.flag()->model(), rt.flag()->state().x, cloth::CrossingScene{});
        most = std::max(most, c.selfEdges);
    }
    return most;
}

}  // namespace

TEST(RuntimeContact, TheDemoFlagWithContactNeverPassesThroughItselfWhereWithoutItDoes) {
    const SceneConfig a = headlessScene("flag_vehicle"), b = headlessScene("flag_vehicle_contact");
    EXPECT_FALSE(a.flag.contact.enabled);
    EXPECT_TRUE(b.flag.contact.enabled);
    EXPECT_TRUE(b.flag.contact.self);
    EXPECT_GT(mostSelfCrossings("flag_vehicle", 150), 0);  // the case is hard: the paper's step folds through itself
    EXPECT_EQ(mostSelfCrossings("flag_vehicle_contact", 150), 0);
}
