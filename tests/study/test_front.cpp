// The front's judges (tools/study/cpp/bounds.h, extreme_runs.h) against computations written here:
// the bounds at their edges, and the trajectory error against a loop over restarted horizons
// written out in the test on a small case.

#include <gtest/gtest.h>

#include <cmath>

#include "bounds.h"
#include "extreme_runs.h"

namespace {

study::ExtremeRun run(double p99, double peak, double patchEnergy, bool stable = true) {
    study::ExtremeRun r;
    r.p99Stretch = p99;
    r.peakStretch = peak;
    r.patchEnergyLate[0] = patchEnergy;
    r.stable = stable;
    return r;
}

study::Extreme path(bool flutter) {
    study::Extreme x;
    x.name = flutter ? "fluttering" : "calm";
    x.flutter = flutter;
    return x;
}

}  // namespace

// p99 <= 1.25 ref + 0.01, peak <= 1.5 ref + 0.02, the patch energy 0.5-2x the reference's where
// the flag flutters; an unstable run misses everything at once.
TEST(FrontBounds, EachBoundAtItsEdge) {
    const study::ExtremeRun ref = run(0.08, 0.2, 4.0);
    const study::Extreme flutter = path(true), calm = path(false);
    EXPECT_EQ(study::missedBounds(run(0.11, 0.32, 8.0), ref, flutter), "");       // 1.25 * 0.08 + 0.01 = 0.11; 0.32; 2x
    EXPECT_EQ(study::missedBounds(run(0.1101, 0.32, 2.0), ref, flutter), "p99");
    EXPECT_EQ(study::missedBounds(run(0.11, 0.3201, 2.0), ref, flutter), "peak");
    EXPECT_EQ(study::missedBounds(run(0.11, 0.32, 1.99), ref, flutter), "energy");
    EXPECT_EQ(study::missedBounds(run(0.11, 0.32, 8.01), ref, flutter), "energy");
    EXPECT_EQ(study::missedBounds(run(0.11, 0.32, 8.01), ref, calm), "") << "energy is judged where the flag flutters";
    EXPECT_EQ(study::missedBounds(run(0.5, 0.9, 100), ref, flutter), "p99;peak;energy");
    EXPECT_EQ(study::missedBounds(run(0.01, 0.01, 4.0, false), ref, flutter), "unstable");
    EXPECT_EQ(study::missedBounds(run(NAN, 0.01, 4.0), ref, calm), "p99") << "a NaN figure misses its bound";
}

// horizonError against the same restarted runs written out here: from every reference state at a
// multiple of 0.25 s, the configuration's flag runs a quarter second; the RMS distance to the
// reference over every tick of every horizon, over the flag's width.
TEST(FrontTrajectoryError, EqualsTheRestartedRunsWrittenOut) {
    const engine::SceneConfig demo =
        study::withContact(engine::loadScene(engine::resolveScenePath("flag_vehicle", FLAGSIM_ASSETS_DIR)), false);
    study::Extreme x;
    for (const study::Extreme& e : study::extremes())
        if (e.name == "stop_10g") x = e;
    x.duration = 0.75;
    const engine::SceneConfig s = study::extremeScene(demo, x, 9);
    const engine::PoleMount mount = study::extremeMount(demo);
    const study::ExtremeRun ref = study::runExtreme(study::referenceScene(s, 8), mount, x, true);
    ASSERT_EQ(ref.states.size(), 181u);  // 0.75 s of 240 Hz ticks, and the start

    const double h = 1.0 / 240, width = s.flag.width;
    double sum = 0;
    long count = 0;
    for (int start = 0; start + 60 < 181; start += 60) {
        engine::Flag flag(s, mount, x.carrier(start * h));
        flag.restart(ref.states[start], x.carrier(start * h));
        for (int k = start + 1; k <= start + 60; ++k) {
            const engine::RigidFrame c = x.carrier(k * h);
            flag.tick(h, c, {flag.poleCollider(c)});
            for (cloth::Index i = 0; i < flag.model().particleCount(); ++i)
                sum += (flag.state().x.col(i) - ref.states[k].x.col(i)).squaredNorm() / flag.model().particleCount();
            ++count;
        }
    }
    const double expected = std::sqrt(sum / count) / width;
    const double got = study::horizonError(s, mount, x, ref.states, h);
    EXPECT_GT(expected, 1e-4) << "the paper's step should drift from the reference";
    EXPECT_NEAR(got, expected, 1e-12 * expected);
}
