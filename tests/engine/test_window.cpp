// The SDL2 window path renders the same picture as the headless path. Needs a display: ctest runs
// it under xvfb-run; without a display it skips.

#include <gtest/gtest.h>

#include <cstdlib>

#include "engine/runtime.h"

using namespace engine;

TEST(Window, RendersTheSameSceneAsHeadless) {
    if (!std::getenv("DISPLAY")) GTEST_SKIP() << "no DISPLAY (run under xvfb-run)";
    SceneConfig s = loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/hanging_flag.json");
    s.subsystems &= ~kRecording;
    s.render.width = 320;
    s.render.height = 240;
    RunOptions o;
    o.frames = 20;
    o.readback = true;
    Runtime headless(s, o);
    while (headless.frame()) {
    }
    RunOptions w = o;
    w.window = true;
    const int windowsBefore = subsystemCounters().windows;
    Runtime window(s, w);
    while (window.frame()) {
    }
    EXPECT_EQ(subsystemCounters().windows, windowsBefore + 1);
    const auto& a = headless.pixels();
    const auto& b = window.pixels();
    ASSERT_EQ(a.size(), b.size());
    double sum = 0;
    int bad = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const int d = std::abs(int(a[i]) - int(b[i]));
        sum += d;
        bad += d > 24;
    }
    EXPECT_LT(sum / a.size(), 1.5) << "mean channel difference";
    EXPECT_LT(bad, int(a.size() / 200)) << "channels off by more than 24 levels";
}
