#include "nvidia_newton_export.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cloth/air.h"
#include "cloth/solver.h"
#include "engine/flag/flag.h"
#include "specs.h"

namespace study {

namespace {

using cloth::Points;
using cloth::State;

// What every NVIDIA Newton harness input holds (tools/study/flagstudy/nvidia_newton_study.py reads it): the configuration's
// name, size, stiffness and step, gravity, the cloth (start positions, masses, springs, triangles)
// and its pinned particles. Pin targets per step are appended with pinTargets().
// Points (3 x n) as n triples.
nlohmann::json pointsJson(const Points& p) {
    nlohmann::json j = nlohmann::json::array();
    for (cloth::Index i = 0; i < p.cols(); ++i) j.push_back({p(0, i), p(1, i), p(2, i)});
    return j;
}

nlohmann::json harnessInput(const std::string& name, int size, double k, double h, const cloth::Model& m,
                           const Points& x, const std::vector<cloth::Pin>& pins) {
    nlohmann::json j;
    j["scene"] = name;
    j["size"] = size;
    j["stiffness"] = k;
    j["h"] = h;
    j["gravity"] = {0.0, -9.81, 0.0};
    j["rest_positions"] = pointsJson(x);
    for (cloth::Index i = 0; i < m.particleCount(); ++i) j["masses"].push_back(m.masses()[i]);
    for (const cloth::Spring& sp : m.springs()) j["springs"].push_back({sp.i, sp.j, sp.k, sp.rest, cloth::toString(sp.kind)});
    for (const cloth::Triangle& t : m.triangles()) j["triangles"].push_back({t[0], t[1], t[2]});
    for (const cloth::Pin& p : pins) j["pinned"].push_back(p.particle);
    return j;
}

nlohmann::json pinTargets(const std::vector<cloth::Pin>& pins) {
    nlohmann::json targets = nlohmann::json::array();
    for (const cloth::Pin& p : pins) targets.push_back({p.x.x(), p.x.y(), p.x.z()});
    return targets;
}

void writeHarnessInput(const std::string& path, const nlohmann::json& j) {
    std::ofstream(path + ".tmp") << j.dump() << "\n";
    std::filesystem::rename(path + ".tmp", path);
}

// The external force the harness must apply at one state of the flag, from the library: the air
// (cloth::addAirForces, where the case has air) and the linear drag, -drag m v; zero on pinned
// particles. The harness checks its own (numpy) air model against it before it runs the case.
nlohmann::json airCheck(const cloth::Model& m, const cloth::State& state, const std::vector<cloth::Pin>& pins,
                        const engine::SceneConfig& s) {
    cloth::Points f = cloth::Points::Zero(3, m.particleCount());
    if (s.subsystems & engine::kAir) cloth::addAirForces(m, state, s.air, f);
    for (cloth::Index i = 0; i < m.particleCount(); ++i) f.col(i) -= s.flag.drag * m.masses()[i] * state.v.col(i);
    for (const cloth::Pin& p : pins) f.col(p.particle).setZero();
    return {{"positions", pointsJson(state.x)}, {"velocities", pointsJson(state.v)}, {"force", pointsJson(f)}};
}

// One extreme case at one size, for the NVIDIA Newton harness: the demo's flag as the library builds it (engine::makeFlagCloth)
// (start positions and velocities, masses, springs, triangles, pins), every pin's target and the
// carrier's velocity at the end of every 240 Hz tick, and the air and drag the flag feels (the
// harness applies them as explicit external forces; it has no pole collision).
void exportExtremeForNvidiaNewton(const std::string& dir, const engine::SceneConfig& demo, const Extreme& x, int size) {
    engine::SceneConfig s = extremeScene(demo, x, size);
    s.flag.solver = configOf("kangcho:iterations=1");  // only the pins' path is read from its ticks
    const engine::PoleMount mount = extremeMount(demo);
    cloth::Cloth flag = engine::makeFlagCloth(s, mount, x.carrier(0));
    const cloth::Model& m = flag.model();
    const double h = 1.0 / s.physicsHz;
    nlohmann::json j = harnessInput(x.name, size, s.flag.stiffness.structural, h, m, flag.state().x, flag.pins());
    j["kind"] = "extreme";
    j["jump_at"] = x.jumpAt;
    j["drag"] = s.flag.drag;
    j["air"] = {{"enabled", (s.subsystems & engine::kAir) != 0},
                {"wind", {s.air.wind.x(), s.air.wind.y(), s.air.wind.z()}},
                {"density", s.air.density},
                {"drag_coefficient", s.air.dragCoefficient},
                {"lift_coefficient", s.air.liftCoefficient},
                {"friction_coefficient", s.air.frictionCoefficient}};
    j["velocities"] = pointsJson(flag.state().v);
    int steps = 0;
    const int checkAt = int(x.duration / h / 2);
    for (int k = 1; k * h <= x.duration + 1e-9; ++k, ++steps) {
        const engine::RigidFrame c = x.carrier(k * h);
        flag.step(h, c, {});
        j["pin_positions"].push_back(pinTargets(flag.pins()));
        j["carrier_velocity"].push_back({c.linearVelocity.x(), c.linearVelocity.y(), c.linearVelocity.z()});
        if (k == checkAt) j["air_check"] = airCheck(m, flag.state(), flag.pins(), s);
    }
    j["steps"] = steps;
    writeHarnessInput(dir + "/extreme_" + x.name + "_" + std::to_string(size) + ".json", j);
}

// A part-1 configuration for the NVIDIA Newton harness: the study's flag (studyFlag) of stiffness k at
// rest on the scene's pole, and every pin's target at the end of each of `steps` steps of h.
nlohmann::json configurationInput(const Scene& scene, const cloth::HangingFlag& flag, double k, double h, int steps) {
    const cloth::Model& m = flag.model;
    nlohmann::json j = harnessInput(scene.name, m.gridNx(), k, h, m, startState(m, scene).x, pinsAt(m, scene, 0));
    j["steps"] = steps;
    for (int s = 0; s < steps; ++s) j["pin_positions"].push_back(pinTargets(pinsAt(m, scene, (s + 1) * h)));
    return j;
}

// The flag and the pole motion of one configuration, for the NVIDIA Newton harness
// (tools/study/flagstudy/nvidia_newton_study.py): the same particles, masses, springs, triangles and pins, and every
// pin's target at the end of every step.
void exportForNvidiaNewtonRun(const std::string& dir, const Scene& scene, int n, double k, double h, double duration) {
    const nlohmann::json j = configurationInput(scene, studyFlag(n, k), k, h, int(std::lround(duration / h)));
    writeHarnessInput(dir + "/" + scene.name + "_" + std::to_string(n) + ".json", j);
}

// The check of our vbd against NVIDIA Newton's VBD (study.py check --nvidia-newton): a 9x9 flag
// of the study's stiffness on the first half second of the demo's drive, and our vbd's positions
// at its end at each of kVbdCheckIterations. The harness runs Newton's VBD on the same model as
// far and compares. Both take the springs' own energy (flagstudy/nvidia_newton/models.py), so at
// enough iterations both reach backward Euler's step; at few, their orders of vertices differ.
constexpr int kVbdCheckSize = 9, kVbdCheckSteps = 120;
constexpr int kVbdCheckIterations[] = {10, 100};

nlohmann::json vbdRuns(const Scene& scene, const cloth::Model& m, const State& start, double h) {
    nlohmann::json runs = nlohmann::json::array();
    for (const int iterations : kVbdCheckIterations) {
        auto solver = cloth::makeSolver(configOf("vbd:iterations=" + std::to_string(iterations)));
        State state = start;
        const cloth::Environment env;  // gravity as the harness's (harnessInput), no drag
        for (int s = 0; s < kVbdCheckSteps; ++s) {
            cloth::StepInput in;
            in.h = h;
            in.pins = pinsAt(m, scene, (s + 1) * h);
            if (solver->step(m, env, state, in).status != cloth::StepStatus::Ok) break;
        }
        runs.push_back({{"iterations", iterations}, {"steps", kVbdCheckSteps}, {"positions", pointsJson(state.x)}});
    }
    return runs;
}

void exportVbdCheck(const std::string& dir) {
    const double h = 1.0 / 240, k = 1e4;
    const PolePath path = drivePath(kVbdCheckSteps * h + 0.1);
    const Scene scene{"vehicle_path", &path};
    const cloth::HangingFlag flag = studyFlag(kVbdCheckSize, k);
    nlohmann::json j = configurationInput(scene, flag, k, h, kVbdCheckSteps);
    j["kind"] = "vbd_check";
    j["vbd_check"] = vbdRuns(scene, flag.model, startState(flag.model, scene), h);
    writeHarnessInput(dir + "/vbd_check_" + scene.name + "_" + std::to_string(kVbdCheckSize) + ".json", j);
}

}  // namespace

int exportForNvidiaNewton(const StudyOptions& o, const std::vector<SolveErrorConfig>& configs,
                          const engine::SceneConfig& demo, const std::vector<Extreme>& cases,
                          const std::vector<int>& sizes) {
    std::filesystem::create_directories(o.exportDir);
    for (const SolveErrorConfig& c : configs)
        if (!o.frontOnly && c.k == 1e4 && c.h == 1.0 / 240)
            exportForNvidiaNewtonRun(o.exportDir, *c.scene, c.n, c.k, c.h, solveErrorDuration(o));
    // --quick: the teleport only (the shortest case) at 17x17, to keep CI's run short (at 33x33
    // XPBD's 30 substeps took two minutes of it)
    const std::vector<Extreme> paths = o.quick ? std::vector<Extreme>{extremes()[3]} : cases;
    const std::vector<int> at = o.quick ? std::vector<int>{17} : sizes;
    if (o.front)
        for (const Extreme& x : paths)
            for (const int size : at) exportExtremeForNvidiaNewton(o.exportDir, demo, x, size);
    exportVbdCheck(o.exportDir);
    std::fprintf(stderr, "flag and pole motion written to %s\n", o.exportDir.c_str());
    return 0;
}

}  // namespace study
