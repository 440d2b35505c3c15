// Commands in a running scene, each checked against a run that needs none: a pause shifts the
// run by its frames and changes no bit; single steps while paused add up to the schedule's
// ticks; a solver, stiffness or rate set at frame 0 gives the bits of the scene written that
// way. And the script's events: bad ones are refused naming the file, the field and the value.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "engine/scene/config_error.h"
#include "engine/scene/input_script.h"
#include "engine/runtime.h"
#include "engine/clock/tick_clock.h"

using namespace engine;

namespace {

SceneConfig benchCloth() { return loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/bench_cloth.json"); }

// A script of no actions and these events, in a temporary file.
std::string eventsScript(const std::string& name, const std::string& events) {
    const std::string path = (std::filesystem::temp_directory_path() / name).string();
    std::ofstream(path) << R"({"keyframes": [{"t": 0}], "events": [)" << events << "]}";
    return path;
}

cloth::Points runFrames(const SceneConfig& s, int frames, const std::string& script = {}) {
    RunOptions o;
    o.frames = frames;
    o.scriptPath = script;
    Runtime rt(s, o);
    while (rt.frame()) {
    }
    return rt.flag()->state().x;
}

}  // namespace

TEST(Commands, APauseShiftsTheRunByItsFramesAndChangesNoBit) {
    const std::string script = eventsScript("flagsim_pause.json",
        R"({"frame": 10, "command": "pause", "value": "on"}, {"frame": 20, "command": "pause", "value": "off"})");
    EXPECT_TRUE(runFrames(benchCloth(), 70, script) == runFrames(benchCloth(), 60));
    EXPECT_FALSE(runFrames(benchCloth(), 60, script) == runFrames(benchCloth(), 60));
    std::filesystem::remove(script);
}

TEST(Commands, FourSingleStepsWhilePausedAreOneFramesTicks) {
    // 240 Hz ticks at 60 frames/s: four steps are the ticks of one frame, and the schedule goes on
    // from there.
    const std::string script = eventsScript("flagsim_step.json",
        R"({"frame": 10, "command": "pause", "value": "on"}, {"frame": 11, "command": "step"},
           {"frame": 12, "command": "step"}, {"frame": 13, "command": "step"}, {"frame": 14, "command": "step"},
           {"frame": 15, "command": "pause", "value": "off"})");
    EXPECT_TRUE(runFrames(benchCloth(), 64, script) == runFrames(benchCloth(), 60));
    std::filesystem::remove(script);
}

TEST(Commands, ASettingAtFrameZeroGivesTheBitsOfTheSceneWrittenThatWay) {
    struct Case {
        const char* event;
        void (*edit)(SceneConfig&);
    };
    const Case cases[] = {
        {R"({"frame": 0, "command": "solver", "value": "multigrid:cycles=2"})",
         [](SceneConfig& s) { cloth::parseSolverConfig("multigrid:cycles=2", s.flag.solver, nullptr); }},
        {R"({"frame": 0, "command": "stretch", "value": "3000"})", [](SceneConfig& s) { s.flag.stiffness.structural = 3000; }},
        {R"({"frame": 0, "command": "mass", "value": "0.5"})", [](SceneConfig& s) { s.flag.mass = 0.5; }},
        {R"({"frame": 0, "command": "wind", "value": "-3,0,8"})", [](SceneConfig& s) { s.air.wind = cloth::Vec3(-3, 0, 8); }},
        {R"({"frame": 0, "command": "physics_hz", "value": "120"})", [](SceneConfig& s) { s.physicsHz = 120; }},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.event);
        const std::string script = eventsScript("flagsim_setting.json", c.event);
        SceneConfig edited = benchCloth();
        c.edit(edited);
        const cloth::Points commanded = runFrames(benchCloth(), 30, script);
        EXPECT_TRUE(commanded == runFrames(edited, 30));
        EXPECT_FALSE(commanded == runFrames(benchCloth(), 30)) << "the setting changed nothing";
        std::filesystem::remove(script);
    }
}

TEST(Commands, TheRateChangesFromItsFrameOnAndTheTimeRunsOn) {
    TickClock clock(240, 60, 8, true);
    for (int f = 0; f < 10; ++f)
        for (long long k = clock.ticksDue(f); k > 0; --k) clock.countTick();
    EXPECT_EQ(clock.ticks(), 40);
    clock.setPhysicsHz(120, 10);
    for (int f = 10; f < 20; ++f) {
        EXPECT_EQ(clock.ticksDue(f), 2) << "frame " << f;
        clock.countTick();
        clock.countTick();
    }
    EXPECT_NEAR(clock.simTime(), 20.0 / 60, 1e-12);
}

// A scene without a vehicle records its commands too (the panel's, a script's): the recording
// holds them at their frames and replays to the same bits; a stiffness change shows it replayed
// the command, not nothing.
TEST(Commands, ASceneWithoutAVehicleRecordsItsCommandsAndTheyReplay) {
    const std::string script = eventsScript("flagsim_cloth_events.json",
        R"({"frame": 5, "command": "stretch", "value": "500"}, {"frame": 9, "command": "reset"})");
    const std::string recorded = (std::filesystem::temp_directory_path() / "flagsim_cloth_recorded.json").string();
    RunOptions o;
    o.frames = 30;
    o.scriptPath = script;
    o.recordInput = recorded;
    cloth::Points live;
    {
        Runtime rt(benchCloth(), o);
        while (rt.frame()) {
        }
        live = rt.flag()->state().x;
        ASSERT_EQ(rt.finish(), 0);
    }
    const InputScript again = InputScript::load(recorded);
    ASSERT_EQ(again.events().size(), 2u);
    EXPECT_EQ(again.events()[0].frame, 5);
    EXPECT_EQ(again.events()[0].command.value, "500");
    EXPECT_TRUE(runFrames(benchCloth(), 30, recorded) == live);
    EXPECT_FALSE(runFrames(benchCloth(), 30) == live);
    std::filesystem::remove(script);
    std::filesystem::remove(recorded);
}

// A command the scene cannot take is refused and counted (the panel shows the last one, stderr
// tells each), and the run goes on as it was.
TEST(Commands, ACommandTheSceneCannotTakeIsRefusedAndCounted) {
    SceneConfig s = loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/vehicle_only.json");
    s.subsystems &= ~(kRender | kRecording);
    const std::string script = eventsScript("flagsim_refused.json",
        R"({"frame": 2, "command": "stretch", "value": "500"}, {"frame": 3, "command": "reset"},
           {"frame": 4, "command": "pause", "value": "on"})");
    RunOptions o;
    o.frames = 6;
    o.scriptPath = script;
    Runtime rt(s, o);
    while (rt.frame()) {
    }
    EXPECT_EQ(rt.refusals(), 1) << "the stretch: no flag; a reset without a flag does nothing, a pause is taken";
    std::filesystem::remove(script);
}

TEST(InputScript, ABadEventNamesTheFileTheFieldAndTheValue) {
    struct Case {
        const char* events;
        const char* expected;
    };
    const Case cases[] = {
        {R"({"frame": 3, "command": "warp", "value": "9"})", "events[0].command = \"warp\""},
        {R"({"frame": 3, "command": "warp", "value": "9"})", "unknown command 'warp'"},
        {R"({"frame": 3, "command": "solver", "value": "multigrid:cycles=-2"})", "cycles"},
        {R"({"frame": 3, "command": "mass", "value": "-1"})", "events[0].value = \"-1\": command mass value '-1'"},
        {R"({"frame": 3, "command": "wind", "value": "1,2"})", "three numbers"},
        {R"({"frame": 3, "command": "pause", "value": "maybe"})", "one of on, off"},
        {R"({"frame": 3, "command": "step", "value": "2"})", "takes no value"},
        {R"({"frame": 5, "command": "step"}, {"frame": 4, "command": "step"})", "events[1].frame"},
        {R"({"command": "step"})", "events[0].frame = null: missing"},
        {R"({"frame": 1, "command": "step", "when": 2})", "when"},
    };
    for (const Case& c : cases) {
        const std::string text = std::string(R"({"keyframes": [{"t": 0}], "events": [)") + c.events + "]}";
        try {
            InputScript::parse(text, "bad.json");
            ADD_FAILURE() << c.events << ": accepted";
        } catch (const ConfigError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("bad.json"), std::string::npos) << what;
            EXPECT_NE(what.find(c.expected), std::string::npos) << what;
        }
    }
}

TEST(InputRecorder, WhilePausedTheLastActionsAtATimeAreTheOnesKept) {
    Actions a, b, c;
    b.throttle = 1;
    c.steer = -1;
    InputRecorder r;
    r.record(0.0, a);
    r.record(0.25, b);
    r.record(0.25, c);  // paused at 0.25: c replaces b
    ASSERT_EQ(r.script().keyframes().size(), 2u);
    EXPECT_EQ(r.script().sample(0.25), c);
    r.record(0.25, a);  // back to the previous keyframe's actions: no keyframe needed
    EXPECT_EQ(r.script().keyframes().size(), 1u);
    r.record(7, Command{"reset", ""});
    ASSERT_EQ(r.script().events().size(), 1u);
    EXPECT_EQ(r.script().commandsAt(7), (std::vector<Command>{{"reset", ""}}));
    EXPECT_TRUE(r.script().commandsAt(6).empty());
}
