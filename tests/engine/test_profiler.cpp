#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bullet_zones.h"
#include "engine/profile/profiler.h"

using namespace engine;

TEST(Profiler, SummaryPercentilesMatchNearestRank) {
    Profiler p;
    p.enable(Phase::Render);
    for (int f = 1; f <= 200; ++f) {
        p.beginFrame();
        p.add(Phase::Render, f);  // 1 .. 200 ms
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
    p.enable(Phase::Render);
    for (int f = 0; f < 3; ++f) {
        p.beginFrame();
        p.add(Phase::Render, 1.5);
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

// The columns are the enabled phases in the frame's order, whatever order a scene enables them
// in; a phase the scene did not enable is neither timed nor a column; the last frame's profile
// holds each phase's time and the frame's.
TEST(Profiler, EnabledPhasesInFrameOrderAndAbsentOnesNotTimed) {
    Profiler p;
    p.enable(Phase::Write);
    p.enable(Phase::Input);
    p.enable(Phase::ClothSolve);
    EXPECT_EQ(p.phases(), (std::vector<std::string>{"input", "cloth_solve", "write"}));
    EXPECT_FALSE(p.enabled(Phase::Render));
    p.beginFrame();
    p.add(Phase::ClothSolve, 2.0);
    p.add(Phase::Render, 5.0);  // absent: ignored
    { Profiler::Scope scope(p, Phase::Collision); }
    p.endFrame();
    EXPECT_EQ(p.columns(), (std::vector<std::string>{"input", "cloth_solve", "write", "frame"}));
    ASSERT_EQ(p.rows().at(0).size(), 4u);
    EXPECT_EQ(p.rows()[0][1], 2.0);
    EXPECT_EQ(p.lastFrame()[Phase::ClothSolve], 2.0);
    EXPECT_EQ(p.lastFrame()[Phase::Render], 0.0);
    EXPECT_EQ(p.lastFrame()[Phase::Collision], 0.0);
    EXPECT_EQ(p.lastFrame().frame, p.rows()[0][3]);
    EXPECT_STREQ(phaseName(Phase::ClothForces), "cloth_forces");
}

// A run without a profile.csv keeps a bounded window of rows: the last ones, in order, however
// many frames pass; the CSV numbers them from the run's start.
TEST(Profiler, ARowLimitKeepsTheLastFramesInBoundedMemory) {
    Profiler p;
    p.enable(Phase::ClothSolve);
    p.setRowLimit(3);
    for (int f = 0; f < 10; ++f) {
        p.beginFrame();
        p.add(Phase::ClothSolve, f);
        p.endFrame();
    }
    EXPECT_EQ(p.frameCount(), 10u);
    ASSERT_GE(p.rows().size(), 3u);
    ASSERT_LE(p.rows().size(), 6u);
    for (std::size_t k = 0; k < p.rows().size(); ++k)
        EXPECT_EQ(p.rows()[k][0], double(10 - p.rows().size() + k));
    EXPECT_NE(p.summaryTable().find("(the last " + std::to_string(p.rows().size()) + " of 10 frames)"),
              std::string::npos);
    EXPECT_EQ(p.summary()[0].max, 9.0);
}
