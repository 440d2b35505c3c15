// --trace on the vehicle scene, headless: the written file is parsed and checked on its own
// terms (frames ordered and apart, phases inside their frame, Bullet's zones nested inside the
// "bullet" phase), and each phase's time per frame against profile.csv from the same run.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/scene/config_error.h"
#include "engine/runtime.h"

using namespace engine;

namespace {

// Rounding of the file's microseconds (to the nanosecond) and of their sums.
constexpr double kEps = 1e-3;

struct Event {
    std::string name, cat;
    double ts = 0, dur = 0;  // microseconds
    int frame = -1;          // a frame's args.frame
    int tid = 0;
    double end() const { return ts + dur; }
    bool inside(const Event& o) const { return ts >= o.ts - kEps && end() <= o.end() + kEps; }
};

struct ParsedTrace {
    std::vector<Event> frames, phases, zones, workers;  // each by begin time
    std::map<int, std::string> threadNames;
};

ParsedTrace parseTrace(const nlohmann::json& j) {
    ParsedTrace t;
    for (const auto& e : j.at("traceEvents")) {
        if (e.at("ph") == "M" && e.at("name") == "thread_name")
            t.threadNames[e.at("tid").get<int>()] = e.at("args").at("name").get<std::string>();
        if (e.at("ph") != "X") continue;
        Event ev{e.at("name").get<std::string>(), e.at("cat").get<std::string>(), e.at("ts").get<double>(),
                 e.at("dur").get<double>()};
        ev.tid = e.at("tid").get<int>();
        if (e.contains("args") && e["args"].contains("frame")) ev.frame = e["args"]["frame"].get<int>();
        if (ev.cat == "frame") t.frames.push_back(ev);
        else if (ev.cat == "phase") t.phases.push_back(ev);
        else if (ev.cat == "bullet") t.zones.push_back(ev);
        else if (ev.cat == "worker") t.workers.push_back(ev);
        else ADD_FAILURE() << "unknown category " << ev.cat;
    }
    for (auto* v : {&t.frames, &t.phases, &t.zones, &t.workers})
        std::stable_sort(v->begin(), v->end(), [](const Event& a, const Event& b) {
            return a.ts != b.ts ? a.ts < b.ts : a.dur > b.dur;
        });
    return t;
}

// The frame (index) an event lies in, or -1.
int frameOf(const ParsedTrace& t, const Event& e) {
    for (std::size_t f = 0; f < t.frames.size(); ++f)
        if (e.inside(t.frames[f])) return int(f);
    return -1;
}

// What breaks the nesting: frames out of order (their index against their time) or overlapping, a phase outside every frame or
// overlapping another phase, a zone outside every "bullet" phase or across another zone's end.
std::vector<std::string> nestingProblems(const ParsedTrace& t) {
    std::vector<std::string> out;
    for (std::size_t f = 0; f < t.frames.size(); ++f) {
        if (t.frames[f].frame != int(f))
            out.push_back("frame " + std::to_string(f) + " in time is frame " + std::to_string(t.frames[f].frame));
        if (f + 1 < t.frames.size() && t.frames[f].end() > t.frames[f + 1].ts + kEps)
            out.push_back("frames " + std::to_string(f) + " and next overlap");
    }
    for (std::size_t i = 0; i < t.phases.size(); ++i) {
        if (frameOf(t, t.phases[i]) < 0) out.push_back(t.phases[i].name + " outside every frame");
        if (i + 1 < t.phases.size() && t.phases[i].end() > t.phases[i + 1].ts + kEps)
            out.push_back(t.phases[i].name + " overlaps " + t.phases[i + 1].name);
    }
    std::vector<const Event*> open;  // the zones enclosing the current one
    for (const Event& z : t.zones) {
        const bool inBullet = std::any_of(t.phases.begin(), t.phases.end(),
                                          [&](const Event& p) { return p.name == "bullet" && z.inside(p); });
        if (!inBullet) out.push_back("zone " + z.name + " outside every bullet phase");
        while (!open.empty() && open.back()->end() <= z.ts + kEps) open.pop_back();
        if (!open.empty() && !z.inside(*open.back())) out.push_back("zone " + z.name + " crosses " + open.back()->name);
        open.push_back(&z);
    }
    return out;
}

// Milliseconds per frame and profile column: the phases by name, the frame itself, and the
// second level of Bullet's zones as "bullet:<zone>" (the profile's columns).
std::map<std::pair<int, std::string>, double> sumsPerFrame(const ParsedTrace& t) {
    std::map<std::pair<int, std::string>, double> sum;
    for (std::size_t f = 0; f < t.frames.size(); ++f) sum[{int(f), "frame"}] += t.frames[f].dur / 1000;
    for (const Event& p : t.phases) sum[{frameOf(t, p), p.name}] += p.dur / 1000;
    std::vector<const Event*> open;
    for (const Event& z : t.zones) {
        while (!open.empty() && open.back()->end() <= z.ts + kEps) open.pop_back();
        if (open.size() == 1) sum[{frameOf(t, z), "bullet:" + z.name}] += z.dur / 1000;
        open.push_back(&z);
    }
    return sum;
}

struct Csv {
    std::vector<std::string> header;
    std::vector<std::vector<double>> rows;
};

Csv readCsv(const std::string& path) {
    std::ifstream in(path);
    Csv csv;
    std::string line, cell;
    for (bool first = true; std::getline(in, line); first = false) {
        std::stringstream s(line);
        std::vector<double> row;
        while (std::getline(s, cell, ',')) {
            if (first) csv.header.push_back(cell);
            else row.push_back(std::stod(cell));
        }
        if (!first) csv.rows.push_back(row);
    }
    return csv;
}

SceneConfig headlessVehicle() {  // the demo, with contact with the pole (so that contact is traced too)
    SceneConfig s = loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/flag_vehicle.json");
    s.subsystems &= ~(kRender | kRecording | kWindow);
    s.flag.contact.enabled = true, s.flag.contact.self = false;
    return s;
}

}  // namespace

TEST(RuntimeTrace, TheTraceNestsAsItRanAndEachPhaseSumsToItsProfileColumn) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "flagsim_runtime_trace";
    fs::remove_all(dir);
    RunOptions o;
    o.frames = 40;
    o.outDir = dir.string();
    o.tracePath = (dir / "trace.json").string();
    {
        Runtime rt(headlessVehicle(), o);
        while (rt.frame()) {
        }
        ASSERT_EQ(rt.finish(), 0);
    }
    std::ifstream in(o.tracePath);
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_TRUE(j.is_object());
    EXPECT_EQ(j.at("displayTimeUnit"), "ms");
    const ParsedTrace t = parseTrace(j);
    ASSERT_EQ(t.frames.size(), 40u);
    ASSERT_FALSE(t.zones.empty()) << "Bullet's zones were not traced";
    const std::vector<std::string> problems = nestingProblems(t);
    EXPECT_TRUE(problems.empty()) << problems.size() << " problems, the first: " << problems.front();

    const Csv csv = readCsv(o.outDir + "/profile.csv");
    ASSERT_EQ(csv.rows.size(), 40u);
    for (const char* phase : {"input", "bullet", "air", "cloth_forces", "cloth_solve", "collision", "contact", "frame"})
        EXPECT_NE(std::find(csv.header.begin(), csv.header.end(), phase), csv.header.end()) << phase;
    const auto sums = sumsPerFrame(t);
    for (std::size_t f = 0; f < csv.rows.size(); ++f)
        for (std::size_t c = 1; c < csv.header.size(); ++c) {  // column 0 is the frame's index
            const auto it = sums.find({int(f), csv.header[c]});
            const double traced = it == sums.end() ? 0.0 : it->second;
            // profile.csv rounds to 0.1 us; the file's microseconds to 1 ns
            EXPECT_NEAR(traced, csv.rows[f][c], 1e-3) << "frame " << f << ", " << csv.header[c];
        }
    for (const auto& [key, ms] : sums)  // and nothing traced that the profile has no column for
        EXPECT_NE(std::find(csv.header.begin(), csv.header.end(), key.second), csv.header.end())
            << key.second << " in frame " << key.first;
}

TEST(RuntimeTrace, TheChecksFindABrokenTrace) {
    // A frame with the bullet phase and two zones, then a second frame: well-formed, then broken
    // one way at a time.
    const auto make = [] {
        ParsedTrace t;
        t.frames = {{"frame", "frame", 0, 100, 0}, {"frame", "frame", 100, 50, 1}};
        t.phases = {{"bullet", "phase", 10, 40}, {"cloth_solve", "phase", 60, 30}};
        t.zones = {{"internalSingleStepSimulation", "bullet", 11, 30}, {"solveConstraints", "bullet", 12, 5}};
        return t;
    };
    EXPECT_TRUE(nestingProblems(make()).empty());
    ParsedTrace t = make();
    t.phases[1].dur = 45;  // past its frame's end
    EXPECT_FALSE(nestingProblems(t).empty());
    t = make();
    t.frames[0].dur = 101;  // into the next frame
    EXPECT_FALSE(nestingProblems(t).empty());
    t = make();
    std::swap(t.frames[0].frame, t.frames[1].frame);  // indices out of time order
    EXPECT_FALSE(nestingProblems(t).empty());
    t = make();
    t.zones[1].ts = 38;  // across its parent zone's end
    EXPECT_FALSE(nestingProblems(t).empty());
    t = make();
    t.zones[0].ts = 30;  // past the bullet phase's end
    EXPECT_FALSE(nestingProblems(t).empty());
    t = make();
    t.phases[0].dur = 55;  // into the next phase
    EXPECT_FALSE(nestingProblems(t).empty());

    const auto sums = sumsPerFrame(make());
    EXPECT_DOUBLE_EQ(sums.at({0, "bullet"}), 0.040);
    EXPECT_DOUBLE_EQ(sums.at({0, "bullet:solveConstraints"}), 0.005);
    EXPECT_EQ(sums.count({0, "bullet:internalSingleStepSimulation"}), 0u);  // the first level is no column
    EXPECT_DOUBLE_EQ(sums.at({1, "frame"}), 0.050);
}

TEST(RuntimeTrace, ATracePathInAFolderThatDoesNotExistIsRefusedBeforeTheRun) {
    RunOptions o;
    o.frames = 1;
    o.tracePath = (std::filesystem::temp_directory_path() / "flagsim_no_such_folder" / "trace.json").string();
    try {
        Runtime rt(headlessVehicle(), o);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("--trace"), std::string::npos) << what;
        EXPECT_NE(what.find(o.tracePath), std::string::npos) << what;
    }
}

// With the solver on two threads, the pool's second thread is on its own row, and each of its
// spans lies inside the frame loop's span of the stage that split the work: the air inside an
// "air" phase, the step inside one step's cloth_forces .. cloth_solve, the collisions inside a
// "collision" phase.
TEST(RuntimeTrace, TheClothPoolsWorkerRunsInsideThePhaseThatSplitItsWork) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "flagsim_runtime_trace_workers";
    fs::remove_all(dir);
    fs::create_directories(dir);
    SceneConfig s = headlessVehicle();
    ASSERT_TRUE(cloth::parseSolverConfig("multigrid:threads=2", s.flag.solver, nullptr));
    RunOptions o;
    o.frames = 20;
    o.tracePath = (dir / "trace.json").string();
    {
        Runtime rt(s, o);
        while (rt.frame()) {
        }
        ASSERT_EQ(rt.finish(), 0);
    }
    std::ifstream in(o.tracePath);
    const ParsedTrace t = parseTrace(nlohmann::json::parse(in));
    ASSERT_FALSE(t.workers.empty()) << "the pool's worker was not traced";
    EXPECT_TRUE(nestingProblems(t).empty());
    std::map<std::string, int> byStage;
    for (const Event& w : t.workers) {
        EXPECT_NE(w.tid, t.phases.front().tid) << "a worker on the frame loop's row";
        EXPECT_EQ(t.threadNames.count(w.tid), 1u) << "worker row " << w.tid << " has no name";
        ++byStage[w.name];
        bool inside = false;
        for (std::size_t i = 0; i < t.phases.size() && !inside; ++i) {
            const Event& p = t.phases[i];
            if (w.name == "cloth_step" && p.name == "cloth_forces") {
                const auto solve = std::find_if(t.phases.begin() + long(i), t.phases.end(),
                                                [](const Event& q) { return q.name == "cloth_solve"; });
                inside = solve != t.phases.end() && w.ts >= p.ts - kEps && w.end() <= solve->end() + kEps;
            } else if (w.name == p.name) {
                inside = w.inside(p);
            }
        }
        EXPECT_TRUE(inside) << w.name << " at " << w.ts << " us lies outside its stage";
    }
    EXPECT_GT(byStage["cloth_step"], 0);
    EXPECT_GT(byStage["air"], 0);
    fs::remove_all(dir);
}
