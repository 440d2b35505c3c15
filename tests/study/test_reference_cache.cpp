// The front's reference cache (tools/study/cpp/reference_cache.h): an entry is reused only under
// the key of everything that made it. A changed input (the flag's mass, the path, the code's
// version) misses and is recomputed; a corrupt or truncated entry is refused and recomputed; a
// reused run equals the run computed afresh, bit for bit, in every figure and in the states the
// trajectory errors read (every tick's positions, the restart ticks' velocities).

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "reference_cache.h"

namespace {

namespace fs = std::filesystem;

study::Extreme path(const char* name, double duration) {
    for (study::Extreme x : study::extremes())
        if (x.name == name) {
            x.duration = duration;
            return x;
        }
    ADD_FAILURE() << "no path " << name;
    return {};
}

engine::SceneConfig demo() {  // as the study takes it: without contact
    return study::withContact(engine::loadScene(engine::resolveScenePath("flag_vehicle", FLAGSIM_ASSETS_DIR)), false);
}

// A small reference: the demo's flag at 9 per side, 6 substeps a tick.
struct Case {
    engine::SceneConfig scene;
    engine::PoleMount mount;
    study::Extreme x;
    std::string key(const std::string& version = study::integratorVersion()) const {
        return study::referenceKey(scene, mount, x, true, version);
    }
    study::ExtremeRun run() const { return study::runExtreme(scene, mount, x, true); }
};

Case smallCase(const char* name = "stop_10g", double duration = 1.75) {
    const study::Extreme x = path(name, duration);
    return {study::referenceScene(study::extremeScene(demo(), x, 9), 6), study::extremeMount(demo()), x};
}

fs::path freshDir(const char* name) {
    const fs::path d = fs::temp_directory_path() / (std::string("flagsim-cache-") + name + "-" + std::to_string(::getpid()));
    fs::remove_all(d);
    return d;
}

// Every figure, and the states a trajectory error reads, the same bits.
void expectSameRun(const study::ExtremeRun& a, const study::ExtremeRun& b) {
    EXPECT_EQ(a.stable, b.stable);
    EXPECT_EQ(a.failures, b.failures);
    for (auto [x, y] : {std::pair{a.maxStretch, b.maxStretch}, {a.peakStretch, b.peakStretch}, {a.p99Stretch, b.p99Stretch},
                        {a.lateStretch, b.lateStretch}, {a.maxSpeed, b.maxSpeed}, {a.energyMean, b.energyMean},
                        {a.energyLate, b.energyLate}, {a.patchEnergyLate[0], b.patchEnergyLate[0]},
                        {a.patchEnergyLate[2], b.patchEnergyLate[2]}, {a.iterationsMean, b.iterationsMean}})
        EXPECT_EQ(std::memcmp(&x, &y, sizeof x), 0) << x << " vs " << y;
    EXPECT_EQ(a.energyWindows, b.energyWindows);
    ASSERT_EQ(a.states.size(), b.states.size());
    const long restart = std::lround(study::kHorizon * study::kReferenceHz);
    for (std::size_t k = 0; k < a.states.size(); ++k) {
        ASSERT_TRUE(a.states[k].x == b.states[k].x) << "positions at tick " << k;
        if (long(k) % restart == 0) {
            ASSERT_TRUE(a.states[k].v == b.states[k].v) << "velocities at tick " << k;
        }
    }
}

}  // namespace

TEST(ReferenceCache, AReusedRunIsTheRunComputedAfreshBitForBit) {
    const Case c = smallCase();
    const fs::path dir = freshDir("same");
    study::ReferenceCache cache(dir);
    const study::ExtremeRun fresh = c.run();
    const study::ExtremeRun first = cache.get(c.key(), [&] { return c.run(); });
    study::ReferenceCache again(dir);  // as a second process on the same folder
    const study::ExtremeRun reused = again.get(c.key(), [&] { ADD_FAILURE() << "recomputed"; return c.run(); });
    EXPECT_EQ(cache.counts().computed, 1);
    EXPECT_EQ(again.counts().reused, 1);
    expectSameRun(first, fresh);
    expectSameRun(reused, fresh);
    fs::remove_all(dir);
}

TEST(ReferenceCache, AChangedInputIsAnotherEntry) {
    const Case c = smallCase();
    const fs::path dir = freshDir("inputs");
    study::ReferenceCache cache(dir);
    cache.get(c.key(), [&] { return c.run(); });
    Case heavier = c;
    heavier.scene.flag.mass *= 1.01;
    Case otherPath = smallCase("speed_50mps", 1.75);
    otherPath.scene = c.scene;  // the same flag on another carrier
    Case longer = smallCase("stop_10g", 2.0);
    for (const std::string& key : {heavier.key(), otherPath.key(), longer.key(), c.key("another version")})
        EXPECT_FALSE(cache.load(key)) << key;
    EXPECT_TRUE(cache.load(c.key()));
    // and the heavier flag's reference, once computed, is its own
    const study::ExtremeRun h = cache.get(heavier.key(), [&] { return heavier.run(); });
    EXPECT_NE(h.energyMean, cache.load(c.key())->energyMean);
    EXPECT_EQ(cache.counts().computed, 2);
    fs::remove_all(dir);
}

TEST(ReferenceCache, ACorruptOrTruncatedEntryIsRefusedAndRecomputed) {
    const Case c = smallCase();
    const fs::path dir = freshDir("corrupt");
    study::ReferenceCache cache(dir);
    const study::ExtremeRun fresh = cache.get(c.key(), [&] { return c.run(); });
    const std::string file = cache.pathOf(c.key());
    const auto size = fs::file_size(file);
    {  // one byte of a position in the middle of the run flipped
        std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(size / 2));
        char b = 0;
        f.read(&b, 1);
        f.seekp(std::streamoff(size / 2));
        b = char(b ^ 0x10);
        f.write(&b, 1);
    }
    EXPECT_FALSE(cache.load(c.key()));
    EXPECT_EQ(cache.counts().refused, 1);
    const study::ExtremeRun again = cache.get(c.key(), [&] { return c.run(); });
    EXPECT_EQ(cache.counts().computed, 2);
    expectSameRun(again, fresh);
    fs::resize_file(file, size - 100);  // cut short
    EXPECT_FALSE(cache.load(c.key()));
    EXPECT_EQ(cache.counts().refused, 3);
    fs::remove_all(dir);
}
