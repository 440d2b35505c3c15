#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "engine/scene/config_error.h"
#include "engine/scene/input_script.h"

using namespace engine;

namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "flagsim_tests";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / name).string();
    std::ofstream(path) << text;
    return path;
}

std::string scriptError(const std::string& path) {
    try {
        InputScript::load(path);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(InputScript, LinearAndStepInterpolationMatchHandValues) {
    const std::string path = writeTemp("lin.json", R"({"keyframes": [
        {"t": 0, "throttle": 0, "steer": -1},
        {"t": 2, "throttle": 1, "steer": 1, "brake": 0.5}]})");
    const InputScript s = InputScript::load(path);
    EXPECT_DOUBLE_EQ(s.sample(0.5).throttle, 0.25);
    EXPECT_DOUBLE_EQ(s.sample(0.5).steer, -0.5);
    EXPECT_DOUBLE_EQ(s.sample(1.0).brake, 0.25);
    EXPECT_DOUBLE_EQ(s.sample(-1).steer, -1);  // before the first keyframe: the first
    EXPECT_DOUBLE_EQ(s.sample(9).throttle, 1); // after the last: the last
    const InputScript step = InputScript::fromKeyframes(s.keyframes(), InputScript::Interpolation::Step);
    EXPECT_DOUBLE_EQ(step.sample(1.999).throttle, 0);
    EXPECT_DOUBLE_EQ(step.sample(2.0).throttle, 1);
}

TEST(InputScript, RecordedScriptReplaysTheSameActionsAtEveryFrame) {
    InputRecorder rec;
    std::vector<Actions> applied;
    for (int f = 0; f < 300; ++f) {
        Actions a;
        a.throttle = (f / 37) % 2 ? 1.0 : 0.3 * std::sin(f * 0.1);
        a.steer = f > 100 && f < 160 ? -0.7 : 0.0;
        applied.push_back(a);
        rec.record(f / 60.0, a);
    }
    const std::string path = writeTemp("rec.json", "");
    std::string error;
    ASSERT_TRUE(rec.script().save(path, &error)) << error;
    const InputScript replay = InputScript::load(path);
    for (int f = 0; f < 300; ++f) ASSERT_EQ(replay.sample(f / 60.0), applied[f]) << "frame " << f;
}

TEST(InputScript, BadScriptsGiveErrorsNamingFileFieldAndValue) {
    struct Case {
        const char* text;
        const char* expect;
    } cases[] = {
        {R"({"keyframes": []})", "keyframes = []: is empty"},
        {R"({"keyframes": [{"t": 1}, {"t": 0.5}]})", "keyframes[1].t = 0.5: times must increase"},
        {R"({"keyframes": [{"t": 0, "throttle": 2}]})", "keyframes[0].throttle = 2: must be in [-1, 1]"},
        {R"({"keyframes": [{"t": 0, "brake": -0.1}]})", "keyframes[0].brake = -0.1"},
        {R"({"keyframes": [{"t": 0, "thrust": 1}]})", "keyframes[0].thrust = 1: unknown field"},
        {R"({"keyframes": [{"throttle": 1}]})", "keyframes[0].t = null: missing"},
        {R"({"keyframes": [{"t": "soon"}]})", "keyframes[0].t = \"soon\": must be a number"},
        {R"({"interpolation": "cubic", "keyframes": [{"t": 0}]})", "interpolation = \"cubic\""},
        {R"({"keyframes": [{"t": 0}],)", "not valid JSON"},
        {R"({})", "keyframes: missing"},
    };
    int i = 0;
    for (const Case& c : cases) {
        const std::string path = writeTemp("bad" + std::to_string(i++) + ".json", c.text);
        const std::string e = scriptError(path);
        EXPECT_NE(e.find(path), std::string::npos) << e;
        EXPECT_NE(e.find(c.expect), std::string::npos) << "got: " << e << "\nwanted: " << c.expect;
    }
    EXPECT_NE(scriptError("/nonexistent/drive.json").find("/nonexistent/drive.json: cannot open"),
              std::string::npos);
}
