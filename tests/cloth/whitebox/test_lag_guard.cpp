// small_steps' lag guard (small_steps/lag_guard.h), fed step times and barrier waits as a busy
// core would give them, without a clock: a window whose waits exceed its work by the allowance
// sends the next steps to one thread; the first window after a spell that lags again doubles the
// spell; short waits and a single late wait under the allowance send nothing solo; a step whose
// waits exceed its work so far by the allowance parts its threads there and starts a spell.

#include <gtest/gtest.h>

#include <chrono>

#include "small_steps/lag_guard.h"

using namespace cloth;
using std::chrono::microseconds;

namespace {

// One parallel step of `work` with one barrier wait of `wait` (both in microseconds).
void step(LagGuard& g, long work, long wait) {
    g.waited(microseconds(wait));
    g.stepEnded(microseconds(work + wait));
}

int soloRun(LagGuard& g) {
    int n = 0;
    while (g.solo()) ++n;
    return n;
}

}  // namespace

TEST(LagGuard, ShortWaitsAndOneLateWaitUnderTheAllowanceKeepTwoThreads) {
    LagGuard g;
    for (int s = 0; s < 1000; ++s) step(g, 20, 190);  // waits under kMinLag (a thread waking, not one off its core), if summed over the allowance
    step(g, 1500, 2500);                                  // one late wait: 2.5 ms against 1.5 ms of work + 2 ms
    for (int s = 0; s < 100; ++s) step(g, 1500, 0);
    EXPECT_EQ(g.spells(), 0);
    EXPECT_FALSE(g.solo());
}

TEST(LagGuard, ABusyCoreSendsTheStepsSoloForLongerSpells) {
    LagGuard g;
    step(g, 1500, 4000);  // a time slice lost: 4 ms waited against 1.5 ms of work
    ASSERT_EQ(g.spells(), 1) << "a step that waited more than its work and the allowance stayed parallel";
    EXPECT_EQ(soloRun(g), LagGuard::kSoloSteps);
    step(g, 1500, 4000);  // the first window after the spell lags again: twice as long
    EXPECT_EQ(g.spells(), 2);
    EXPECT_EQ(soloRun(g), 2 * LagGuard::kSoloSteps);
    for (int k = 0; k < 20; ++k) {
        step(g, 1500, 4000);
        soloRun(g);
    }
    EXPECT_EQ(g.spellLength(), LagGuard::kMaxSoloSteps) << "the spells stop doubling at the cap";
}

TEST(LagGuard, ACoreThatFreesUpGetsItsThreadBackAfterOneSpell) {
    LagGuard g;
    step(g, 1500, 4000);
    soloRun(g);
    for (int s = 0; s < 3 * LagGuard::kWindow; ++s) step(g, 1500, 0);  // the other core free again
    EXPECT_EQ(g.spells(), 1);
    EXPECT_FALSE(g.solo());
    step(g, 1500, 4000);  // busy again later: a fresh spell, not a doubled one
    EXPECT_EQ(soloRun(g), LagGuard::kSoloSteps);
}

TEST(LagGuard, LateWaitsAddUpWithinAWindow) {
    LagGuard g;
    // 1 ms waits on 0.5 ms steps: each alone under the allowance, together over the window's work.
    for (int s = 0; s < LagGuard::kWindow && g.spells() == 0; ++s) step(g, 500, 1000);
    EXPECT_EQ(g.spells(), 1);
}

TEST(LagGuard, AStepThatWaitsLongerThanItWorksPartsItsThreadsAndStartsASpell) {
    LagGuard g;
    g.waited(microseconds(150));  // under kMinLag: not counted
    EXPECT_FALSE(g.partNow(microseconds(400))) << "a step that waited under kMinLag parted";
    g.waited(microseconds(1900));  // 1.9 ms off its core, after 0.5 ms of work: within the allowance
    EXPECT_FALSE(g.partNow(microseconds(2550)));
    g.waited(microseconds(4000));  // a time slice lost: 5.9 ms waited against 0.65 ms of work
    EXPECT_TRUE(g.partNow(microseconds(6700)));
    EXPECT_TRUE(g.partNow(microseconds(6800))) << "the threads parted for the rest of the step";
    g.stepEnded(microseconds(9000));
    EXPECT_EQ(g.spells(), 1) << "a step whose threads parted did not start a spell";
    EXPECT_EQ(soloRun(g), LagGuard::kSoloSteps);
    g.stepEnded(microseconds(1500));
    EXPECT_FALSE(g.partNow(microseconds(0))) << "the next step began parted";
}
