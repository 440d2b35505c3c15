#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bullet_zones.h"
#include "engine/profiler.h"

using namespace engine;

TEST(Profiler, SummaryPercentilesMatchNearestRank) {
    Profiler p;
    const int a = p.addPhase("a");
    for (int f = 1; f <= 200; ++f) {
        p.beginFrame();
        p.add(a, f);  // 1 .. 200 ms
        p.endFrame();
    }
    const auto s = p.summary();
    EXPECT_DOUBLE_EQ(s[0].mean, 100.5);
    EXPECT_DOUBLE_EQ(s[0].p50, 100);
    EXPECT_DOUBLE_EQ(s[0].p95, 190);
    EXPECT_DOUBLE_EQ(s[0].p99, 198);
    EXPECT_DOUBLE_EQ(s[0].max, 200);
}

TEST(Profiler, CsvHasOneRowPerFrameAndZonesAddedLaterReadZeroBefore) {
    Profiler p;
    const int a = p.addPhase("render");
    for (int f = 0; f < 3; ++f) {
        p.beginFrame();
        p.add(a, 1.5);
        if (f == 2) {  // only the second level of zones becomes a column
            enterAndLeaveBulletZones(p);
        }
        p.endFrame();
    }
    const auto path = (std::filesystem::temp_directory_path() / "flagsim_profile.csv").string();
    std::string error;
    ASSERT_TRUE(p.writeCsv(path, &error)) << error;
    std::ifstream in(path);
    std::string header, line;
    std::getline(in, header);
    EXPECT_EQ(header, "frame_index,render,bullet:stepSimulation,frame");
    int rows = 0;
    while (std::getline(in, line)) {
        if (rows == 0) {
            EXPECT_EQ(line.rfind("0,1.5000,0.0000,", 0), 0u) << line;
        }
        ++rows;
    }
    EXPECT_EQ(rows, 3);
}
