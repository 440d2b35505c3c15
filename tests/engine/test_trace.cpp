// The trace file: Chrome Trace Event JSON with times in microseconds since the trace's origin,
// and the profiler's events with the same clock readings as its profile.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bullet_zones.h"
#include "engine/profile/profiler.h"
#include "engine/profile/trace.h"

using namespace engine;
using namespace std::chrono_literals;

namespace {

nlohmann::json readJson(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

std::string tempPath(const char* name) {
    return (std::filesystem::temp_directory_path() / name).string();
}

}  // namespace

TEST(Trace, WritesCompleteEventsInMicrosecondsSinceItsOriginEnclosingEventsFirst) {
    const Trace::Clock::time_point o{};  // the clock's epoch: times below are exact
    Trace trace(o);
    const int phase = trace.nameId("cloth_solve");
    const int frame = trace.nameId("frame");
    EXPECT_EQ(trace.nameId("cloth_solve"), phase);
    // Recorded as they end: the phase before the frame that encloses it.
    trace.complete(phase, Trace::Category::Phase, o + 1500ns, o + 4000ns);
    trace.complete(frame, Trace::Category::Frame, o + 1000ns, o + 10000ns, 7);
    const std::string path = tempPath("flagsim_trace_unit.json");
    std::string error;
    ASSERT_TRUE(trace.write(path, &error)) << error;
    const nlohmann::json j = readJson(path);
    EXPECT_EQ(j.at("displayTimeUnit"), "ms");
    const auto& ev = j.at("traceEvents");
    ASSERT_EQ(ev.size(), 4u);
    EXPECT_EQ(ev[0].at("ph"), "M");
    EXPECT_EQ(ev[0].at("name"), "process_name");
    EXPECT_EQ(ev[1].at("ph"), "M");
    EXPECT_EQ(ev[1].at("name"), "thread_name");
    EXPECT_EQ(ev[1].at("tid"), 1);

    EXPECT_EQ(ev[2].at("ph"), "X");
    EXPECT_EQ(ev[2].at("name"), "frame");
    EXPECT_EQ(ev[2].at("cat"), "frame");
    EXPECT_DOUBLE_EQ(ev[2].at("ts").get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(ev[2].at("dur").get<double>(), 9.0);
    EXPECT_EQ(ev[2].at("args").at("frame"), 7);
    EXPECT_EQ(ev[3].at("name"), "cloth_solve");
    EXPECT_EQ(ev[3].at("cat"), "phase");
    EXPECT_DOUBLE_EQ(ev[3].at("ts").get<double>(), 1.5);
    EXPECT_DOUBLE_EQ(ev[3].at("dur").get<double>(), 2.5);
    EXPECT_FALSE(ev[3].contains("args"));
    for (std::size_t i = 2; i < ev.size(); ++i) {
        EXPECT_EQ(ev[i].at("pid"), ev[1].at("pid"));
        EXPECT_EQ(ev[i].at("tid"), ev[1].at("tid"));
    }
}

TEST(Trace, AFolderThatDoesNotExistFailsNamingThePathAndLeavesNothing) {
    Trace trace;
    trace.complete(trace.nameId("frame"), Trace::Category::Frame, Trace::Clock::now(), Trace::Clock::now(), 0);
    const std::string path = tempPath("flagsim_no_such_folder/trace.json");
    std::string error;
    EXPECT_FALSE(trace.write(path, &error));
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(Trace, ProfilerRecordsFramesPhasesAndEveryZoneLevelWithItsProfileTimes) {
    Profiler p;
    Trace trace;
    p.setTrace(&trace);
    p.enable(Phase::Bullet);
    p.beginFrame();
    {
        Profiler::Scope scope(p, Phase::Bullet);
        enterAndLeaveBulletZones(p);
    }
    p.endFrame();
    const auto& ev = trace.events();
    ASSERT_EQ(ev.size(), 5u);  // three zones, the phase, the frame: in the order they ended
    const auto name = [&](std::size_t i) { return trace.names()[ev[i].name]; };
    EXPECT_EQ(name(0), "deeper");
    EXPECT_EQ(name(1), "stepSimulation");
    EXPECT_EQ(name(2), "internalSingleStepSimulation");
    EXPECT_EQ(name(3), "bullet");
    EXPECT_EQ(name(4), "frame");
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(ev[i].category, Trace::Category::Zone);
    EXPECT_EQ(ev[3].category, Trace::Category::Phase);
    EXPECT_EQ(ev[4].category, Trace::Category::Frame);
    EXPECT_EQ(ev[4].frame, 0);
    // The profile's row holds the durations the events carry: bullet, bullet:stepSimulation, frame.
    const auto& row = p.rows().at(0);
    ASSERT_EQ(p.columns(), (std::vector<std::string>{"bullet", "bullet:stepSimulation", "frame"}));
    EXPECT_DOUBLE_EQ(row[0], Profiler::ms(ev[3].duration));
    EXPECT_DOUBLE_EQ(row[1], Profiler::ms(ev[1].duration));
    EXPECT_DOUBLE_EQ(row[2], Profiler::ms(ev[4].duration));
}

TEST(Trace, AProfilerWithoutATraceRecordsNothingAndStillProfiles) {
    Profiler p;
    Trace trace;
    p.setTrace(&trace);
    p.setTrace(nullptr);
    p.enable(Phase::Render);
    p.beginFrame();
    { Profiler::Scope scope(p, Phase::Render); }
    p.endFrame();
    EXPECT_TRUE(trace.events().empty());
    EXPECT_EQ(p.frameCount(), 1u);
}
