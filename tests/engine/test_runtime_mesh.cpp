// --export-mesh on cloth-only scenes: the flag's mesh of every frame as DIR/flag_NNNNNN.obj, read
// back here by a reader of this file's own (not the writer's code) and held to the flag's state
// bit for bit; one file per frame and no temporary left; the refused cases; a failed write.

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "engine/runtime.h"
#include "engine/scene/config_error.h"

using namespace engine;
namespace fs = std::filesystem;

namespace {

SceneConfig meshScene(const char* name) {
    return loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/" + name + ".json");
}

fs::path freshDir(const char* name) {
    const fs::path d = fs::temp_directory_path() / name;
    fs::remove_all(d);
    return d;
}

// A Wavefront OBJ as --export-mesh writes it: comment lines, `v x y z`, `f a b c` (1-based).
struct Obj {
    std::string firstLine;
    std::vector<std::array<double, 3>> vertices;
    std::vector<std::array<long, 3>> faces;
};

Obj readObj(const fs::path& path) {
    Obj obj;
    std::ifstream in(path);
    EXPECT_TRUE(in) << path;
    std::string line;
    bool first = true;
    while (std::getline(in, line)) {
        if (first) obj.firstLine = line;
        first = false;
        if (line.empty() || line[0] == '#') continue;
        std::istringstream fields(line);
        std::string tag, a, b, c, extra;
        fields >> tag >> a >> b >> c;
        EXPECT_FALSE(fields >> extra) << path << ": more than three numbers in: " << line;
        if (tag == "v") {
            std::array<double, 3> v{};
            const std::string* text[3] = {&a, &b, &c};
            for (int k = 0; k < 3; ++k) {
                char* end = nullptr;
                v[k] = std::strtod(text[k]->c_str(), &end);
                EXPECT_EQ(*end, '\0') << path << ": not a number: " << *text[k];
            }
            obj.vertices.push_back(v);
        } else if (tag == "f") {
            obj.faces.push_back({std::stol(a), std::stol(b), std::stol(c)});
        } else {
            ADD_FAILURE() << path << ": unexpected line: " << line;
        }
    }
    return obj;
}

std::set<std::string> filesIn(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

// The message of the ConfigError that constructing the runtime throws (empty: none).
std::string refusal(const SceneConfig& s, const RunOptions& o) {
    try {
        Runtime rt(s, o);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return {};
}

}  // namespace

TEST(RuntimeMesh, TheLastMeshReadsBackToTheFlagsStateBitForBit) {
    const fs::path dir = freshDir("flagsim_mesh_readback");
    RunOptions o;
    o.frames = 5;
    o.exportMeshDir = dir.string();
    Runtime rt(meshScene("bench_cloth"), o);
    while (rt.frame()) {
    }
    ASSERT_EQ(rt.finish(), 0);
    const cloth::Points& x = rt.flag()->state().x;
    const auto& triangles = rt.flag()->model().triangles();

    const Obj last = readObj(dir / "flag_000004.obj");
    EXPECT_EQ(last.firstLine.rfind("# ", 0), 0u) << last.firstLine;
    for (const std::string& part : {std::string("bench_cloth"), std::string("frame 4"),
                                    std::string("solver ") + cloth::describe(rt.scene().flag.solver)})
        EXPECT_NE(last.firstLine.find(part), std::string::npos) << last.firstLine << " does not name " << part;
    char time[40];
    std::snprintf(time, sizeof time, "time %.17g s", rt.simTime());
    EXPECT_NE(last.firstLine.find(time), std::string::npos) << last.firstLine << " does not give " << time;

    ASSERT_EQ(last.vertices.size(), std::size_t(x.cols()));
    int differing = 0;
    for (std::size_t p = 0; p < last.vertices.size(); ++p)
        for (int k = 0; k < 3; ++k)
            if (std::bit_cast<std::uint64_t>(last.vertices[p][k]) != std::bit_cast<std::uint64_t>(x(k, Eigen::Index(p))))
                ++differing;
    EXPECT_EQ(differing, 0) << "coordinates that do not read back to the state's bits";
    ASSERT_EQ(last.faces.size(), triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(last.faces[t][k], long(triangles[t][k]) + 1) << "triangle " << t;

    // Each frame has its own state: the flag moves in the wind between the first and the last.
    const Obj firstFrame = readObj(dir / "flag_000000.obj");
    ASSERT_EQ(firstFrame.vertices.size(), last.vertices.size());
    EXPECT_NE(firstFrame.vertices, last.vertices);
    EXPECT_NE(firstFrame.firstLine.find("frame 0"), std::string::npos) << firstFrame.firstLine;
}

TEST(RuntimeMesh, OneFilePerFrameNoneHalfWrittenInItsOwnPhase) {
    const fs::path dir = freshDir("flagsim_mesh_frames");
    const fs::path out = freshDir("flagsim_mesh_out");
    RunOptions o;
    o.frames = 7;
    o.exportMeshDir = dir.string();
    o.outDir = out.string();
    Runtime rt(meshScene("bench_cloth"), o);  // no render: a mesh per frame all the same
    while (rt.frame()) {
    }
    ASSERT_EQ(rt.finish(), 0);
    std::set<std::string> expected;
    for (int f = 0; f < 7; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "flag_%06d.obj", f);
        expected.insert(name);
    }
    EXPECT_EQ(filesIn(dir), expected);  // nothing else: no temporary name left
    for (const std::string& name : expected) {
        const Obj obj = readObj(dir / name);
        EXPECT_EQ(obj.vertices.size(), std::size_t(rt.flag()->state().x.cols())) << name;
        EXPECT_EQ(obj.faces.size(), rt.flag()->model().triangles().size()) << name << " is cut short";
    }
    EXPECT_EQ(rt.profiler().phases(), (std::vector<std::string>{"air", "cloth_forces", "cloth_solve", "export_mesh"}));
    std::ifstream summaryFile(out / "summary.json");
    const auto summary = nlohmann::json::parse(summaryFile);
    EXPECT_EQ(summary["export_mesh"]["files_written"].get<int>(), 7);
    EXPECT_EQ(summary["export_mesh"]["error"].get<std::string>(), "");
}

TEST(RuntimeMesh, RefusedBeforeTheRunWithOneLine) {
    const fs::path file = freshDir("flagsim_mesh_file");
    std::ofstream(file) << "not a folder";
    RunOptions o;
    o.frames = 1;
    o.exportMeshDir = file.string();
    EXPECT_EQ(refusal(meshScene("bench_cloth"), o), "--export-mesh " + file.string() + ": is a file, not a folder");

    const fs::path dir = freshDir("flagsim_mesh_nocloth");
    o.exportMeshDir = dir.string();
    EXPECT_EQ(refusal(meshScene("vehicle_only"), o),
              "--export-mesh " + dir.string() + ": scene 'vehicle_only' has no cloth (no 'cloth' subsystem), so there "
              "is no mesh to export");
    EXPECT_FALSE(fs::exists(dir));

    o.exportMeshDir = (dir / "inner" / "meshes").string();
    EXPECT_EQ(refusal(meshScene("bench_cloth"), o),
              "--export-mesh " + o.exportMeshDir + ": folder " + (dir / "inner").string() + " does not exist");

    // A non-empty folder as --out's: refused, and with --force only an earlier run's meshes go.
    fs::create_directories(dir);
    std::ofstream(dir / "flag_000009.obj") << "an earlier run";
    std::ofstream(dir / "keep.txt") << "mine";
    o.exportMeshDir = dir.string();
    EXPECT_EQ(refusal(meshScene("bench_cloth"), o),
              "--export-mesh " + dir.string() + ": folder exists and is not empty (use --force to write into it)");
    o.force = true;
    EXPECT_EQ(refusal(meshScene("bench_cloth"), o), "");
    EXPECT_EQ(filesIn(dir), (std::set<std::string>{"keep.txt"}));
}

// The folder replaced by a file after the start: the first frame's write fails, the run goes on,
// finish reports the mesh's path and why and returns 1, and the profile and summary are written.
TEST(RuntimeMesh, AFailedWriteIsReportedAtTheEndAndTheRunCompletes) {
    const fs::path dir = freshDir("flagsim_mesh_gone");
    const fs::path out = freshDir("flagsim_mesh_gone_out");
    RunOptions o;
    o.frames = 4;
    o.exportMeshDir = dir.string();
    o.outDir = out.string();
    Runtime rt(meshScene("bench_cloth"), o);
    fs::remove_all(dir);
    std::ofstream(dir) << "in the way";
    while (rt.frame()) {
    }
    testing::internal::CaptureStderr();
    const int code = rt.finish();
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(code, 1);
    EXPECT_EQ(err, "flagsim: error: " + dir.string() + "/flag_000000.obj: cannot write: Not a directory\n");
    EXPECT_EQ(rt.frameIndex(), 4);
    std::ifstream summaryFile(out / "summary.json");
    const auto summary = nlohmann::json::parse(summaryFile);
    EXPECT_EQ(summary["frames"].get<int>(), 4);
    EXPECT_EQ(summary["export_mesh"]["files_written"].get<int>(), 0);
    EXPECT_NE(summary["export_mesh"]["error"].get<std::string>().find("cannot write"), std::string::npos);
    EXPECT_TRUE(fs::exists(out / "profile.csv"));
}
