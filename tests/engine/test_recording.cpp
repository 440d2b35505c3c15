// Recording integrity: an interrupted recording leaves only complete frames and a valid profile;
// a full disk is a clear error; an existing output folder is not overwritten without --force; the
// summary counts the solver's iterations and contact's work; --export-mesh is refused or writes a mesh per frame.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "engine/record/frame_writer.h"

namespace fs = std::filesystem;

namespace {

fs::path freshDir(const char* name) {
    const fs::path d = fs::temp_directory_path() / name;
    fs::remove_all(d);
    return d;
}

// Runs flagsim with the arguments (stdout discarded, stderr to `stderrPath` when given); returns
// its pid.
pid_t spawnDemo(const std::vector<std::string>& args, const std::string& stderrPath = {}) {
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> argv;
        static std::string exe = FLAGSIM_EXE;
        argv.push_back(exe.data());
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        std::freopen("/dev/null", "w", stdout);
        if (!stderrPath.empty()) std::freopen(stderrPath.c_str(), "w", stderr);
        execv(exe.c_str(), argv.data());
        _exit(127);
    }
    return pid;
}

int waitExit(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

TEST(Recording, InterruptedRunLeavesOnlyCompleteFramesAndAValidProfile) {
    for (int sig : {SIGINT, SIGTERM}) {
        const fs::path out = freshDir("flagsim_interrupted");
        const pid_t pid = spawnDemo({"--scene", "hanging_flag", "--out", out.string(), "--frames", "100000",
                                     "--width", "320", "--height", "240", "--no-progress"});
        // Wait until frames are being written, then interrupt.
        for (int i = 0; i < 200 && !(fs::exists(out / "frames") && !fs::is_empty(out / "frames")); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        kill(pid, sig);
        EXPECT_EQ(waitExit(pid), 130) << "signal " << sig;

        int frames = 0;
        for (const auto& e : fs::directory_iterator(out / "frames")) {
            const std::string name = e.path().filename().string();
            EXPECT_EQ(name.rfind("frame_", 0), 0u) << "leftover " << name;
            int w = 0, h = 0;
            std::vector<std::uint8_t> rgba;
            EXPECT_TRUE(engine::readPng(e.path().string(), w, h, rgba)) << name << " does not decode";
            EXPECT_EQ(w, 320);
            ++frames;
        }
        EXPECT_GT(frames, 0);
        std::ifstream summaryFile(out / "summary.json");
        const auto summary = nlohmann::json::parse(summaryFile);
        EXPECT_EQ(summary["stop_reason"], "interrupted");
        EXPECT_EQ(summary["recording"]["frames_written"].get<int>(), frames);
        std::ifstream csv(out / "profile.csv");
        std::string line;
        int rows = -1;
        while (std::getline(csv, line)) ++rows;
        EXPECT_EQ(rows, summary["frames"].get<int>());
        EXPECT_EQ(rows, frames);
    }
}

// kangcho with three Jacobi sweeps reports three iterations every step and no linear solve; newton
// capped at two iterations reports one or two, each with at least one GMRES iteration.
TEST(Recording, TheSummaryCountsTheSolversIterationsPerStep) {
    const auto cloth = [](const std::string& solver) {
        const fs::path out = freshDir("flagsim_iterations");
        const pid_t pid = spawnDemo({"--scene", "hanging_flag", "--out", out.string(), "--frames", "12", "--force",
                                     "--no-frames", "--width", "160", "--height", "120", "--solver", solver});
        EXPECT_EQ(waitExit(pid), 0) << solver;
        std::ifstream summaryFile(out / "summary.json");
        return nlohmann::json::parse(summaryFile)["cloth"];
    };
    const auto jacobi = cloth("kangcho:iterations=3");
    EXPECT_GT(jacobi["steps"].get<int>(), 0);
    EXPECT_EQ(jacobi["iterations_mean"].get<double>(), 3.0);
    EXPECT_EQ(jacobi["iterations_max"].get<int>(), 3);
    EXPECT_EQ(jacobi["linear_iterations_mean"].get<double>(), 0.0);
    const auto newton = cloth("newton:max_iterations=2");
    EXPECT_GE(newton["iterations_mean"].get<double>(), 1.0);
    EXPECT_LE(newton["iterations_max"].get<int>(), 2);
    EXPECT_GE(newton["linear_iterations_mean"].get<double>(), newton["iterations_mean"].get<double>());
}

// The main demo's first second: contact's work summed over the run. The flag hangs beside its pole,
// so every step has edges near it and cuts its motion into at least one sub-interval; nothing is
// overloaded; its broad phase takes part of its time. Without contact the summary has no "contact".
TEST(Recording, TheSummaryCountsContactsWork) {
    const auto summary = [](const std::string& scene) {
        const fs::path out = freshDir("flagsim_contact_summary");
        EXPECT_EQ(waitExit(spawnDemo({"--scene", scene, "--out", out.string(), "--frames", "60", "--force", "--no-frames",
                                      "--width", "160", "--height", "120"})),
                  0);
        std::ifstream summaryFile(out / "summary.json");
        return nlohmann::json::parse(summaryFile);
    };
    const auto demo = summary("flag_vehicle");
    ASSERT_TRUE(demo.contains("contact"));
    const auto& c = demo["contact"];
    EXPECT_GE(c["subintervals"].get<long long>(), demo["cloth"]["steps"].get<long long>());
    EXPECT_GT(c["near_solids"].get<long long>(), 0);
    EXPECT_EQ(c["overloaded_steps"].get<long long>(), 0);
    // The broad phase is part of contact's time: over 0, under the profile's contact summed over the frames.
    const double contactMs = demo["profile"]["contact"]["mean_ms"].get<double>() * demo["frames"].get<double>();
    EXPECT_GT(c["broad_phase_ms"].get<double>(), 0);
    EXPECT_LE(c["broad_phase_ms"].get<double>(), contactMs);
    EXPECT_FALSE(summary("flag_vehicle_no_contact").contains("contact"));
}

// The main demo's first 2.5 s without contact, where the paper's step folds through itself: its
// crossings counted after each frame's ticks (the default) and after every tick. The frames' states
// are some of the ticks' states, so every tick finds at least what the frames do; each run counts as
// often as it says.
TEST(Recording, TheSummaryCountsCrossingsAfterEachFrameOrAfterEveryTick) {
    const auto crossings = [](bool everyTick) {
        const fs::path out = freshDir(everyTick ? "flagsim_crossings_tick" : "flagsim_crossings_frame");
        std::vector<std::string> args = {"--scene", "flag_vehicle_no_contact", "--out", out.string(), "--frames", "150",
                                         "--force", "--no-frames", "--width", "160", "--height", "120"};
        if (everyTick) args.push_back("--crossings-every-tick");
        EXPECT_EQ(waitExit(spawnDemo(args)), 0);
        std::ifstream summaryFile(out / "summary.json");
        return nlohmann::json::parse(summaryFile)["crossings"];
    };
    const auto frame = crossings(false), tick = crossings(true);
    EXPECT_EQ(frame["counted_after"], "each frame's ticks");
    EXPECT_EQ(tick["counted_after"], "every tick");
    EXPECT_EQ(frame["counts"].get<int>(), 150);
    EXPECT_EQ(tick["counts"].get<int>(), 150 * 4);  // 240 Hz ticks, 60 frames a second
    EXPECT_GT(frame["max_in_one_count"].get<int>(), 0);
    EXPECT_GE(tick["max_in_one_count"].get<int>(), frame["max_in_one_count"].get<int>());
    EXPECT_GE(tick["counts_with_crossings"].get<int>(), frame["counts_with_crossings"].get<int>());
}

TEST(Recording, ExistingOutputFolderNeedsForce) {
    const fs::path out = freshDir("flagsim_existing");
    fs::create_directories(out);
    std::ofstream(out / "keep.txt") << "mine";
    const pid_t pid = spawnDemo({"--scene", "hanging_flag", "--out", out.string(), "--frames", "2"});
    EXPECT_EQ(waitExit(pid), 2);
    EXPECT_FALSE(fs::exists(out / "frames"));
    EXPECT_TRUE(fs::exists(out / "keep.txt"));
}

TEST(Recording, FullDiskIsAClearErrorNotACrash) {
    const fs::path dir = freshDir("flagsim_full");
    fs::create_directories(dir);
    if (mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") != 0)
        GTEST_SKIP() << "cannot mount a small tmpfs here (needs root)";
    {
        engine::FrameWriter writer(dir.string(), 256, 256, 2);
        std::vector<std::uint8_t> noise(256 * 256 * 4);
        std::uint32_t seed = 1;
        for (auto& b : noise) b = std::uint8_t((seed = seed * 1664525u + 1013904223u) >> 24);
        for (int i = 0; i < 10; ++i) writer.push(i, noise);  // ~260 KB each: the disk fills
        EXPECT_FALSE(writer.finish());
        EXPECT_NE(writer.error().find("No space left"), std::string::npos) << writer.error();
        for (const auto& e : fs::directory_iterator(dir))
            EXPECT_EQ(e.path().filename().string().rfind(".tmp", 0), std::string::npos) << "half-written file left";
    }
    umount(dir.c_str());
}

namespace {

// Runs flagsim to completion; returns its exit code and what it printed on stderr.
std::pair<int, std::string> runDemo(const std::vector<std::string>& args) {
    // One file per test process: ctest runs the tests of this file in parallel processes.
    const fs::path err = fs::temp_directory_path() / ("flagsim_stderr_" + std::to_string(getpid()) + ".txt");
    const pid_t pid = spawnDemo(args, err.string());
    const int code = waitExit(pid);
    std::string text;
    {
        std::ifstream in(err);
        text.assign(std::istreambuf_iterator<char>(in), {});
    }
    fs::remove(err);
    return {code, text};
}

}  // namespace

TEST(CommandLine, BadOptionsGiveAClearErrorAndANonZeroExit) {
    struct Case {
        std::vector<std::string> args;
        std::string expect;
    } cases[] = {
        {{"--frames", "-5"}, "--frames"},
        {{"--frames", "many"}, "--frames"},
        {{"--width", "5"}, "--width"},
        {{"--bogus"}, "--bogus"},
        {{"--scene", "nosuch"}, "nosuch.json: cannot open file"},
        {{"--solver", "magic"}, "--solver magic: unknown solver 'magic'"},
        {{"--solver", "kangcho:iterations=-2"}, "iterations"},
        {{"--script", "/nonexistent/drive.json", "--frames", "1"}, "/nonexistent/drive.json: cannot open file"},
        {{"--aa", "blur"}, "--aa"},
    };
    for (const Case& c : cases) {
        const auto [code, err] = runDemo(c.args);
        std::string joined;
        for (const auto& a : c.args) joined += a + " ";
        EXPECT_NE(code, 0) << joined;
        EXPECT_NE(err.find(c.expect), std::string::npos) << joined << "\nstderr: " << err;
    }
}

// --export-mesh is refused before the run starts, in one line and with exit code 2: a path that is
// a file, a scene without a cloth (its folder is not made).
TEST(CommandLine, ExportMeshIsRefusedInOneLineBeforeTheRun) {
    const fs::path file = freshDir("flagsim_mesh_cli_file");
    std::ofstream(file) << "not a folder";
    const fs::path dir = freshDir("flagsim_mesh_cli");
    const struct {
        std::vector<std::string> args;
        std::string stderrText;
    } cases[] = {
        {{"--scene", "bench_cloth", "--frames", "2", "--export-mesh", file.string()},
         "flagsim: error: --export-mesh " + file.string() + ": is a file, not a folder\n"},
        {{"--scene", "vehicle_only", "--frames", "2", "--export-mesh", dir.string()},
         "flagsim: error: --export-mesh " + dir.string() +
             ": scene 'vehicle_only' has no cloth (no 'cloth' subsystem), so there is no mesh to export\n"},
    };
    for (const auto& c : cases) {
        const auto [code, err] = runDemo(c.args);
        EXPECT_EQ(code, 2) << c.args[1];
        EXPECT_EQ(err, c.stderrText) << c.args[1];
    }
    EXPECT_FALSE(fs::exists(dir));
}

// A cloth scene without rendering exports a mesh per frame, and nothing else, into the folder.
TEST(Recording, ExportMeshWritesAnObjPerFrame) {
    const fs::path dir = freshDir("flagsim_mesh_cli_frames");
    const auto [code, err] = runDemo({"--scene", "bench_cloth", "--frames", "3", "--export-mesh", dir.string(), "--no-progress"});
    EXPECT_EQ(code, 0) << err;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"flag_000000.obj", "flag_000001.obj", "flag_000002.obj"}));
}
