// The fixed-step clock: the lockstep schedule, and the wall clock's accumulator with its cap.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "engine/clock/tick_clock.h"

using namespace engine;
using std::chrono::milliseconds;

namespace {

// Runs the ticks a frame is due, as the runtime does.
long long runFrame(TickClock& clock, int frame, TickClock::Clock::time_point now) {
    const long long due = clock.ticksDue(frame, now);
    for (long long k = 0; k < due; ++k) clock.countTick();
    return due;
}

}  // namespace

TEST(TickClock, LockstepRunsExactlyTheScheduleWhateverTheWallClockDoes) {
    // 100 Hz at 30 fps: 10 ticks every 3 frames, as 3, 3, 4. The wall clock jumps around and
    // changes nothing, and max_ticks_per_frame (2 here) does not apply.
    TickClock clock(100, 30, 2, /*lockstep=*/true);
    const auto t0 = TickClock::Clock::time_point{};
    clock.startWall(t0);
    std::vector<long long> due;
    const long long jumps[] = {0, 5000, 1, 70, 0, 100000};
    for (int f = 0; f < 6; ++f) due.push_back(runFrame(clock, f, t0 + milliseconds(jumps[f])));
    EXPECT_EQ(due, (std::vector<long long>{3, 3, 4, 3, 3, 4}));
    EXPECT_EQ(clock.ticks(), 20);
    EXPECT_DOUBLE_EQ(clock.simTime(), 20 * 0.01);

    // The demo's 240 Hz at 60 fps: 4 a frame for a long run, floor((k + 1) * 240 / 60) in all.
    TickClock demo(240, 60, 8, true);
    for (int f = 0; f < 10000; ++f) ASSERT_EQ(runFrame(demo, f, t0), 4) << "frame " << f;
    EXPECT_EQ(demo.ticks(), 40000);
    EXPECT_EQ(demo.simTime(), 40000 * (1.0 / 240));
}

TEST(TickClock, LockstepCatchesUpTicksAFrameDidNotRun) {
    // The schedule counts from the ticks really run: a frame that ran fewer is made up next.
    TickClock clock(240, 60, 8, true);
    EXPECT_EQ(clock.ticksDue(0), 4);
    clock.countTick();
    EXPECT_EQ(clock.ticksDue(1), 7);
}

TEST(TickClock, WallClockRunsTheElapsedWholeTicksAndKeepsTheRemainder) {
    // 64 Hz: a tick is 15.625 ms. 40 ms run 2 ticks and keep 8.75 ms; 40 ms more make 48.75 ms,
    // 3 ticks, and keep 1.875 ms; 5 ms more make 6.875 ms, none.
    TickClock clock(64, 60, 8, /*lockstep=*/false);
    const auto t0 = TickClock::Clock::time_point{} + milliseconds(1000);
    clock.startWall(t0);
    EXPECT_EQ(runFrame(clock, 0, t0 + milliseconds(40)), 2);
    EXPECT_EQ(runFrame(clock, 1, t0 + milliseconds(80)), 3);
    EXPECT_EQ(runFrame(clock, 2, t0 + milliseconds(85)), 0);
    EXPECT_EQ(clock.ticks(), 5);
    EXPECT_DOUBLE_EQ(clock.simTime(), 5 / 64.0);
}

TEST(TickClock, WallClockCapsAtMaxTicksPerFrameAndDropsTheBacklog) {
    TickClock clock(64, 60, 8, /*lockstep=*/false);
    const auto t0 = TickClock::Clock::time_point{} + milliseconds(1000);
    clock.startWall(t0);
    // Exactly the cap (8 ticks = 125 ms, plus 10 ms) runs 8 and keeps the remainder.
    EXPECT_EQ(runFrame(clock, 0, t0 + milliseconds(135)), 8);
    EXPECT_EQ(runFrame(clock, 1, t0 + milliseconds(145)), 1);  // 10 + 10 ms
    // A one-second stall: 64 ticks due, 8 run, the other 56 and the remainder dropped.
    EXPECT_EQ(runFrame(clock, 2, t0 + milliseconds(1145)), 8);
    EXPECT_EQ(runFrame(clock, 3, t0 + milliseconds(1165)), 1);  // 20 ms, not the backlog
    EXPECT_EQ(runFrame(clock, 4, t0 + milliseconds(1170)), 0);  // 4.375 + 5 ms
    EXPECT_EQ(clock.ticks(), 18);
}
