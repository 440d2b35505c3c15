// cloth_study: error against run time, and stability on stiff and extreme cases.
//
//   cloth_study [--quick] [--out DIR]      (tools/run study [--quick] runs it and plots)
//   cloth_study --help                     (every option: subsets of scenes, sizes and solvers)
//
// Part 1 (error_vs_runtime.csv): every solver on the same cloth, masses and pins, per scene
// (hanging flag; flag on a pole following the vehicle path of the demo's `drive` script), size,
// stiffness and time step. Metrics (words as in docs/algorithm.md):
//   ms_per_step          median over repeats in this process
//   solve_error          median |dv - dv_exact| / |dv_exact| over 24 states sampled along the run
//                        (implicit solvers; dv_exact: sparse Cholesky up to 65x65, multigrid to a
//                        relative residual of 1e-10 above)
//   traj_error_be        RMS distance to the converged backward Euler run (exact, same h), over
//                        0.25 s horizons restarted from states along that run, / cloth size
//   traj_error_fine      the same against exact backward Euler at h/16 (full run, small sizes)
//   max_stretch, p99_stretch over the run; energy_growth: max (E - E0) / (m g height)
//   stable, fail_step
// Part 2 (extreme.csv): the demo's flag (engine::Flag with assets/scenes/flag_vehicle.json, or the
// scene given by --extreme-scene) and the stiff scene's flag on a carrier driven through extreme
// motions (tools/study/extreme_cases.h), per configuration, judged against the flag's fine-step
// reference (`reference`, `stiff_reference`: tools/study/extreme_runs.h): stable or not, stretch,
// the kinetic energy in the carrier's frame (mean, last second, per 0.5 s window), and the
// trajectory error over 0.25 s horizons restarted from the reference's states.
// extreme_cases.csv: per case, the largest speed and acceleration its carrier gives the flag's
// pinned column; the study stops before any work when a case moves no pin and has no wind (it
// would test nothing).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cloth/air.h"
#include "cloth/diagnostics.h"
#include "cloth/presets.h"
#include "cloth/multigrid_settings.h"
#include "cloth/solver.h"
#include "engine/flag.h"
#include "engine/input_script.h"
#include "engine/physics/vehicle_world.h"
#include "engine/scene.h"
#include "peer/bullet_cloth.h"
#include "extreme_cases.h"
#include "extreme_runs.h"

using cloth::Points;
using cloth::State;
using cloth::Vec3;
using Clock = std::chrono::steady_clock;
using study::Extreme;
using study::extremeMount;
using study::extremes;
using study::extremeScene;

namespace {

// A pole pose over time: position and velocity of its top, and its rotation (the flag's
// pinned column hangs from the top along the pole).
struct PolePath {
    std::vector<Eigen::Isometry3d> pose;  // per step of the finest h used with it
    std::vector<Vec3> linear, angular;
    double dt = 0;
};

// The chassis path of the demo's drive script, from the demo's own vehicle (Bullet).
PolePath drivePath(double duration) {
    const engine::InputScript script = engine::InputScript::load(std::string(FLAGSIM_ASSETS_DIR) + "/scripts/drive.json");
    engine::VehicleWorld world({});
    PolePath p;
    p.dt = 1.0 / 960;
    for (int k = 0; k * p.dt <= duration + 1e-9; ++k) {
        const engine::Actions a = script.sample(k * p.dt);
        world.setControls({a.throttle, a.brake, a.steer, a.handbrake});
        world.stepTick(p.dt);
        const engine::RigidPose c = world.chassis();
        Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
        t.linear() = c.rotation.toRotationMatrix();
        t.translation() = c.position;
        p.pose.push_back(t);
        p.linear.push_back(c.linearVelocity);
        p.angular.push_back(c.angularVelocity);
    }
    return p;
}

struct Scene {
    std::string name;
    const PolePath* path = nullptr;  // null: fixed pole
};

// Pins of column 0 for the carrier pose at time t (rest positions in the carrier frame).
std::vector<cloth::Pin> pinsAt(const cloth::Model& m, const Scene& s, double t) {
    std::vector<cloth::Pin> pins = cloth::pinColumn(m);
    if (!s.path) return pins;
    const std::size_t k = std::min(s.path->pose.size() - 1, std::size_t(std::lround(t / s.path->dt)));
    const Eigen::Isometry3d& T = s.path->pose[k];
    for (cloth::Pin& p : pins) {
        const Vec3 local = m.restPositions().col(p.particle);
        p.x = T * local;
        p.v = s.path->linear[k] + s.path->angular[k].cross(p.x - T.translation());
    }
    return pins;
}

State startState(const cloth::Model& m, const Scene& s) {
    State st = State::atRest(m);
    if (s.path) {
        const Eigen::Isometry3d& T = s.path->pose[0];
        for (cloth::Index i = 0; i < m.particleCount(); ++i) st.x.col(i) = T * Vec3(m.restPositions().col(i));
    }
    return st;
}

// One stepping method: a cloth::Solver by spec, or Bullet's btSoftBody.
struct Method {
    std::string family, spec;
    bool bullet = false;
    int bulletIterations = 1;
    void (*tune)(cloth::MultigridTuning&) = nullptr;  // multigrid: its settled tuning changed
    std::string tuning = {};  // the tuning's name, after the spec in the row's label: "multigrid/stationary"
};

void stationaryCycles(cloth::MultigridTuning& t) { t.krylov = false; }

// A solver from a spec the study itself wrote: a spec that does not parse is a bug in the study,
// never a silent run of the default solver under the wrong label.
cloth::SolverConfig configOf(const std::string& spec, void (*tune)(cloth::MultigridTuning&) = nullptr) {
    cloth::SolverConfig c;
    std::string error;
    if (!cloth::parseSolverConfig(spec, c, &error)) {
        std::fprintf(stderr, "cloth_study: solver spec '%s': %s\n", spec.c_str(), error.c_str());
        std::exit(2);
    }
    if (tune) {
        auto& m = c.get<cloth::MultigridSettings>();
        cloth::MultigridTuning t = cloth::settledTuning(m);
        tune(t);
        m.tuning = t;
    }
    return c;
}

// The constraints after the '|' of a "solver|constraints" spec the study wrote (none without one).
cloth::Constraints constraintsOf(const std::string& spec) {
    const std::size_t bar = spec.find('|');
    cloth::Constraints c;
    std::string error;
    if (bar != std::string::npos && !cloth::parseConstraints(spec.substr(bar + 1), c, &error)) {
        std::fprintf(stderr, "cloth_study: constraints '%s': %s\n", spec.c_str() + bar + 1, error.c_str());
        std::exit(2);
    }
    return c;
}

struct Runner {
    const cloth::Model& model;
    cloth::Environment env;
    std::unique_ptr<cloth::Solver> solver;
    std::unique_ptr<peer::BulletCloth> bullet;
    State state;
    bool ok = true;
    Runner(const cloth::Model& m, const Method& method, const State& s, const std::vector<cloth::Pin>& pins)
        : model(m), state(s) {
        if (method.bullet) bullet = std::make_unique<peer::BulletCloth>(m, s, pins, method.bulletIterations);
        else solver = cloth::makeSolver(configOf(method.spec, method.tune));
    }
    void step(double h, const std::vector<cloth::Pin>& pins) {
        if (bullet) {  // Bullet pins are fixed nodes: move them to their targets by hand
            bullet->step(h);
            bullet->positions(state.x);
            return;
        }
        cloth::StepInput in;
        in.h = h;
        in.pins = pins;
        ok = ok && solver->step(model, env, state, in).status == cloth::StepStatus::Ok;
    }
};

// The exact dv of the step from `before`: Cholesky where it is affordable, else multigrid to a
// relative residual of 1e-10 (the tests check the two agree).
Points exactDv(const cloth::Model& m, const cloth::Environment& env, const State& before, const cloth::StepInput& in) {
    auto solver = cloth::makeSolver(configOf(m.particleCount() > 65 * 65 ? "exact:method=multigrid" : "exact"));
    State s = before;
    if (solver->step(m, env, s, in).status != cloth::StepStatus::Ok) return {};
    return solver->lastDv();
}

struct Row {
    std::string scene, family, solver;
    int size;
    double k, h;
    double ms = NAN, solveErr = NAN, trajBE = NAN, trajFine = NAN, maxStretch = NAN, p99Stretch = NAN,
           energyGrowth = NAN;
    bool stable = true;
    int failStep = -1;
};

double energy(const cloth::Model& m, const cloth::Environment& env, const State& s) {
    const cloth::Diagnostics d = cloth::measure(m, env, s);
    return d.kinetic + d.potential;
}

// The study's flag: n x n, structural and shear stiffness k, bend k/10 (the rest as
// cloth::HangingFlagDesc says).
cloth::HangingFlag studyFlag(int n, double k) {
    cloth::HangingFlagDesc d;
    d.nx = d.ny = n;
    d.stiffness = {k, k, k / 10};
    return cloth::makeHangingFlag(d);
}

double rms(const Points& a, const Points& b) { return std::sqrt((a - b).colwise().squaredNorm().mean()); }

Row runOne(const Scene& scene, int n, double k, double h, const Method& method, double duration,
           const std::vector<State>& reference, bool fine, const std::vector<State>& fineRef, int fineEvery) {
    const cloth::HangingFlag flag = studyFlag(n, k);
    const cloth::HangingFlagDesc d;  // studyFlag keeps its width and height
    const cloth::Model& m = flag.model;
    Row r{scene.name, method.family, method.bullet ? "bullet:iterations=" + std::to_string(method.bulletIterations)
                                        : method.spec + (method.tuning.empty() ? "" : "/" + method.tuning), n, k, h};
    const int steps = int(std::lround(duration / h));
    const State start = startState(m, scene);
    Runner run(m, method, start, pinsAt(m, scene, 0));
    const double scale = m.totalMass() * 9.81 * d.height;
    const double e0 = energy(m, run.env, start);
    double maxGrowth = 0, maxStretch = 0, p99 = 0;
    std::vector<double> errors;
    std::vector<double> stepMs;
    for (int s = 0; s < steps; ++s) {
        const auto pins = pinsAt(m, scene, (s + 1) * h);
        const bool sample = !method.bullet && method.family != "explicit" && s % std::max(1, steps / 24) == 3;
        State before;
        if (sample) before = run.state;
        const auto t0 = Clock::now();
        run.step(h, pins);
        stepMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        const cloth::Diagnostics diag = cloth::measure(m, run.env, run.state, true);
        // Bounds are measured from the pole top (particle 0, pinned), wherever the pole is.
        if (!run.ok || cloth::instability(diag, run.state, run.state.x.col(0))) {
            r.stable = false;
            r.failStep = s;
            break;
        }
        maxStretch = std::max(maxStretch, diag.maxStretch);
        p99 = std::max(p99, diag.p99Stretch);
        if (!scene.path) maxGrowth = std::max(maxGrowth, (energy(m, run.env, run.state) - e0) / scale);
        if (sample) {
            cloth::StepInput in;
            in.h = h;
            in.pins = pins;
            const Points exact = exactDv(m, run.env, before, in);
            if (exact.size()) errors.push_back((run.solver->lastDv() - exact).norm() / std::max(exact.norm(), 1e-300));
        }
    }
    std::nth_element(stepMs.begin(), stepMs.begin() + stepMs.size() / 2, stepMs.end());
    r.ms = stepMs.empty() ? NAN : stepMs[stepMs.size() / 2];
    r.maxStretch = maxStretch;
    r.p99Stretch = p99;
    r.energyGrowth = scene.path ? NAN : maxGrowth;
    if (!errors.empty()) {
        std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
        r.solveErr = errors[errors.size() / 2];
    }
    if (!r.stable || method.bullet) return r;

    // Trajectory errors over 0.25 s horizons restarted along the reference run.
    auto horizonError = [&](const std::vector<State>& ref, int every) {
        const int horizon = std::max(1, int(std::lround(0.25 / h)));
        double sum = 0;
        int count = 0;
        for (int startStep = 0; startStep + horizon < int(ref.size()) / every; startStep += horizon) {
            Runner hr(m, method, ref[std::size_t(startStep) * every], {});
            for (int s = startStep; s < startStep + horizon; ++s) {
                hr.step(h, pinsAt(m, scene, (s + 1) * h));
                if (!hr.ok) return double(NAN);
                const double e = rms(hr.state.x, ref[std::size_t(s + 1) * every].x);
                sum += e * e;
                ++count;
            }
        }
        return count ? std::sqrt(sum / count) / d.width : double(NAN);
    };
    if (!reference.empty()) r.trajBE = horizonError(reference, 1);
    if (fine && !fineRef.empty()) r.trajFine = horizonError(fineRef, fineEvery);
    return r;
}

std::vector<State> referenceRun(const Scene& scene, int n, double k, double h, double duration) {
    const cloth::HangingFlag flag = studyFlag(n, k);
    Runner run(flag.model, {"exact", "exact"}, startState(flag.model, scene), {});
    std::vector<State> states{run.state};
    const int steps = int(std::lround(duration / h));
    for (int s = 0; s < steps; ++s) {
        run.step(h, pinsAt(flag.model, scene, (s + 1) * h));
        if (!run.ok) return {};
        states.push_back(run.state);
    }
    return states;
}

// What every Newton harness input holds (tools/study/newton_study.py reads it): the configuration's
// name, size, stiffness and step, gravity, the cloth (start positions, masses, springs, triangles)
// and its pinned particles. Pin targets per step are appended with pinTargets().
// Points (3 x n) as n triples.
nlohmann::json pointsJson(const Points& p) {
    nlohmann::json j = nlohmann::json::array();
    for (cloth::Index i = 0; i < p.cols(); ++i) j.push_back({p(0, i), p(1, i), p(2, i)});
    return j;
}

nlohmann::json newtonInput(const std::string& name, int size, double k, double h, const cloth::Model& m,
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

void writeNewtonInput(const std::string& path, const nlohmann::json& j) {
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

}  // namespace

// One extreme case at one size, for the Newton harness: the demo's flag as engine::Flag builds it
// (start positions and velocities, masses, springs, triangles, pins), every pin's target and the
// carrier's velocity at the end of every 240 Hz tick, and the air and drag the flag feels (the
// harness applies them as explicit external forces; it has no pole collision).
void exportExtremeForNewton(const std::string& dir, const engine::SceneConfig& demo, const Extreme& x, int size) {
    engine::SceneConfig s = extremeScene(demo, x, size);
    s.flag.solver = configOf("kangcho:iterations=1");  // only the pins' path is read from its ticks
    const engine::PoleMount mount = extremeMount(demo);
    engine::Flag flag(s, mount, x.carrier(0));
    const cloth::Model& m = flag.model();
    const double h = 1.0 / s.physicsHz;
    nlohmann::json j = newtonInput(x.name, size, s.flag.stiffness.structural, h, m, flag.state().x, flag.pins());
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
        flag.tick(h, c, {});
        j["pin_positions"].push_back(pinTargets(flag.pins()));
        j["carrier_velocity"].push_back({c.linearVelocity.x(), c.linearVelocity.y(), c.linearVelocity.z()});
        if (k == checkAt) j["air_check"] = airCheck(m, flag.state(), flag.pins(), s);
    }
    j["steps"] = steps;
    writeNewtonInput(dir + "/extreme_" + x.name + "_" + std::to_string(size) + ".json", j);
}

// The flag and the pole motion of one configuration, for the Newton harness
// (tools/study/newton_study.py): the same particles, masses, springs, triangles and pins, and every
// pin's target at the end of every step.
void exportForNewton(const std::string& dir, const Scene& scene, int n, double k, double h, double duration) {
    const cloth::HangingFlag flag = studyFlag(n, k);
    const cloth::Model& m = flag.model;
    const State start = startState(m, scene);
    const int steps = int(std::lround(duration / h));
    nlohmann::json j = newtonInput(scene.name, n, k, h, m, start.x, pinsAt(m, scene, 0));
    j["steps"] = steps;
    for (int s = 0; s < steps; ++s) j["pin_positions"].push_back(pinTargets(pinsAt(m, scene, (s + 1) * h)));
    writeNewtonInput(dir + "/" + scene.name + "_" + std::to_string(n) + ".json", j);
}

// Keeps the items of `all` named in `names` (none: all), in that order; false with the first
// unknown name in `unknown`.
template <class Item>
bool chooseByName(std::vector<Item>& all, const std::vector<std::string>& names, std::string& unknown) {
    if (names.empty()) return true;
    std::vector<Item> chosen;
    for (const std::string& name : names) {
        const auto it = std::find_if(all.begin(), all.end(), [&](const Item& x) { return x.name == name; });
        if (it == all.end()) return unknown = name, false;
        chosen.push_back(*it);
    }
    all = std::move(chosen);
    return true;
}

const char* kUsage = R"(usage: cloth_study [options]

The solver study: error against run time on a hanging flag and on a flag following the demo's
vehicle path, a scan over stiffness and time step, and the demo's flag in six extreme cases.

  --quick              a small grid (sizes 17 and 33, three stiffnesses and time steps, 0.5 s)
  --out DIR            where the CSV files go (default out/study)
  --scenes LIST        comma-separated subset of: hanging_flag, vehicle_path
  --sizes LIST         comma-separated grid sides, e.g. 17,33,65,129 (overrides the size list)
  --solvers LIST       semicolon-separated solver specs to run instead of the default set,
                       e.g. "multigrid;multigrid:cycles=1;exact" (family = the name before ':')
  --no-scan            skip the stiffness and time-step scan
  --no-extremes        skip the extreme cases (extreme.csv)
  --no-trajectories    no traj_error in extreme.csv (no run against each case's reference)
  --extremes-only      only the extreme cases
  --configs LIST       comma-separated subset of the extreme-case configurations (by name)
  --cases LIST         comma-separated subset of the extreme cases (by name, e.g. spin_5radps)
  --stiff-configs L    more configurations of the stiff flag: NAME=SPEC@HZ or NAME=SPEC@HZxSUBSTEPS,
                       ';'-separated
                       (e.g. "bdf2_90=newton:integrator=bdf2@90"); pick them with --configs
  --extreme-sizes LIST flag sides for the extreme cases (default 33,65, --quick 33; the flag keeps
                       its aspect)
  --extreme-scene S    whose flag the extreme cases run (a scene name or a .json path; default
                       flag_vehicle): its size, mass, stiffness, air, physics rate and, as
                       demo_default, its solver
  --shard K/N          run only the K-th of N disjoint parts of the work (rows keep their serial
                       numbers; tools/study/merge_shards.py joins the parts)
  --export-newton DIR  write the flag and pole motion of every k=1e4, h=1/240 configuration, and of
                       every extreme case and size (--quick: the teleport), as JSON for
                       tools/study/newton_study.py, then stop
  --parallel           mark the timing columns as taken while other shards ran (timing=parallel)
  --help               this text
)";

// shard.json: which part of the work this run holds and how many rows the whole run has, so that
// merge_shards.py can tell a complete set of shards from an incomplete one.
void writeShardInfo(const std::string& out, int shard, int shards, long configRows, long extremeRows) {
    std::ofstream f(out + "/shard.json");
    f << "{\"shard\": " << shard << ", \"of\": " << shards << ", \"rows\": {\"error_vs_runtime.csv\": " << configRows
      << ", \"extreme.csv\": " << extremeRows << "}}\n";
}

std::vector<std::string> split(const std::string& text, char sep) {
    std::vector<std::string> parts;
    std::size_t at = 0;
    while (at <= text.size()) {
        const std::size_t next = text.find(sep, at);
        const std::string part = text.substr(at, next == std::string::npos ? std::string::npos : next - at);
        if (!part.empty()) parts.push_back(part);
        if (next == std::string::npos) break;
        at = next + 1;
    }
    return parts;
}

// A comma-separated list of grid sides in [lo, hi] into `out`; the error names the option and the
// value, or is empty.
std::string readSides(const std::string& option, const std::string& text, long lo, long hi, std::vector<int>& out) {
    for (const std::string& v : split(text, ',')) {
        char* end = nullptr;
        const long n = std::strtol(v.c_str(), &end, 10);
        if (*end != '\0' || n < lo || n > hi)
            return option + ": '" + v + "' is not a side in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        out.push_back(int(n));
    }
    return {};
}

// The guard on every extreme case (tools/study/extreme_cases.h): its carrier moves the flag's
// pins, or it has wind. Writes each case's largest pin speed and acceleration to `csv` (unless
// empty); false, with the reason on stderr, when a case drives nothing.
bool extremeCasesDriveTheFlag(const engine::SceneConfig& demo, const std::string& csv) {
    const std::vector<study::CaseMotion> motions = study::caseMotions(demo, extremes());
    if (!csv.empty()) {
        std::ofstream f(csv);
        f << "case,wind,pin_speed_max,pin_accel_max\n";
        char line[200];
        for (const study::CaseMotion& c : motions) {
            std::snprintf(line, sizeof line, "%s,%g,%.4g,%.4g\n", c.name.c_str(), c.wind, c.pins.speedMax, c.pins.accelMax);
            f << line;
        }
    }
    const std::string idle = study::idleCases(motions);
    if (!idle.empty()) std::fprintf(stderr, "cloth_study: %s", idle.c_str());
    return idle.empty();
}

// "HZ" or "HZxSUBSTEPS" (--stiff-configs): a physics rate, and the substeps of each of its ticks.
bool parseRate(const char* text, int& hz, int& substeps) {
    char rest = 0;
    substeps = 1;
    const int read = std::sscanf(text, "%dx%d%c", &hz, &substeps, &rest);
    if (read == 1 && std::sscanf(text, "%d%c", &hz, &rest) != 1) return false;  // "240x" or "240abc"
    return (read == 1 || read == 2) && hz > 0 && substeps > 0;
}

// An extreme-case configuration: a solver on one of the two flags, at a physics rate; or the
// fine-step reference of that flag (referenceFactor > 0: the reference's substeps times it).
struct Variant {
    std::string name, solver;  // "solver spec|constraints" (constraints.h; no '|': none)
    int substeps;
    int implicitAir = -1;  // -1: as the scene says, else 0 / 1
    bool stiff = false;    // the stiff scene's flag, else the demo's
    int hz = 0;            // physics rate (0: the scene's)
    int referenceFactor = 0;
};

// The reference's substeps per tick at 33 per side (extreme_runs.h scales them with the size and
// the mass): the demo's soft flag, and the stiff flag (k = 1e4).
constexpr int kDemoReferenceSubsteps = 24, kStiffReferenceSubsteps = 160;

// The extreme cases' part of the study: each case x size x configuration a row of extreme.csv,
// the configurations judged against their flag's reference (computed once per case, size and flag).
class ExtremeStudy {
public:
    // trajectories: whether the configurations get traj_error (each a run against the reference).
    ExtremeStudy(const engine::SceneConfig& demo, const engine::SceneConfig& stiff, bool trajectories)
        : demo_(demo), stiff_(stiff), trajectories_(trajectories) {}
    // The patch energy columns name kPatchCounts in order.
    static_assert(study::kPatchCounts == std::array<int, 3>{8, 4, 16});
    static const char* header() {
        return "row,case,size,config,stable,failures,ms_per_tick,timing,max_stretch,peak_stretch,p99_stretch,"
               "late_max_stretch,max_speed,physics_hz,ke_mean,ke_late,ke_windows,traj_error,iterations_mean,"
               "iterations_max,ke_patch_late,ke_patch4_late,ke_patch16_late\n";
    }
    std::string row(long index, const Extreme& x, int size, const Variant& v, const char* timing) {
        const engine::SceneConfig s = sceneOf(x, size, v);
        const engine::PoleMount mount = extremeMount(demo_);
        const bool needsReference = v.referenceFactor == 1 || trajectories_;
        const study::ExtremeRun* ref = needsReference ? &reference(x, size, v.stiff) : nullptr;
        study::ExtremeRun own;
        const study::ExtremeRun& r = v.referenceFactor == 1 ? *ref : (own = study::runExtreme(s, mount, x, false));
        const double traj = v.referenceFactor == 1 ? 0.0
                            : r.stable && ref ? study::horizonError(s, mount, x, ref->states, hOf(*ref, x))
                                              : NAN;
        std::string windows;
        for (double e : r.energyWindows) {
            if (!windows.empty()) windows += ';';
            windows += fmt(e);
        }
        char line[700];
        std::snprintf(line, sizeof line, "%ld,%s,%d,%s,%d,%d,%.4g,%s,%.4g,%.4g,%.4g,%.4g,%.4g,%g,%.4g,%.4g,%s,%.4g,%.4g,%d,%.4g,%.4g,%.4g\n",
                      index, x.name.c_str(), size, v.name.c_str(), r.stable ? 1 : 0, r.failures, r.msPerTick, timing,
                      r.maxStretch, r.peakStretch, r.p99Stretch, r.lateStretch, r.maxSpeed, double(s.physicsHz), r.energyMean,
                      r.energyLate, windows.c_str(), traj, r.iterationsMean, r.iterationsMax, r.patchEnergyLate[0],
                      r.patchEnergyLate[1], r.patchEnergyLate[2]);
        return line;
    }

private:
    static std::string fmt(double v) {
        char b[32];
        std::snprintf(b, sizeof b, "%.4g", v);
        return b;
    }
    static double hOf(const study::ExtremeRun& ref, const Extreme& x) { return x.duration / double(ref.states.size() - 1); }
    engine::SceneConfig sceneOf(const Extreme& x, int size, const Variant& v) const {
        engine::SceneConfig s = extremeScene(v.stiff ? stiff_ : demo_, x, size);
        if (v.referenceFactor > 0) {
            const int base = v.stiff ? kStiffReferenceSubsteps : kDemoReferenceSubsteps;
            return study::referenceScene(s, v.referenceFactor * study::referenceSubsteps(base, size, x));
        }
        s.flag.solver = configOf(v.solver.substr(0, v.solver.find('|')));
        s.flag.constraints = constraintsOf(v.solver);
        s.flag.substeps = v.substeps;
        if (v.implicitAir >= 0) s.flag.implicitAir = v.implicitAir == 1;
        if (v.hz > 0) s.physicsHz = v.hz;
        return s;
    }
    const study::ExtremeRun& reference(const Extreme& x, int size, bool stiff) {
        const std::string key = x.name + "/" + std::to_string(size) + (stiff ? "/stiff" : "/demo");
        auto it = references_.find(key);
        if (it == references_.end()) {
            const Variant ref{"reference", "", 1, -1, stiff, 0, 1};
            it = references_.emplace(key, study::runExtreme(sceneOf(x, size, ref), extremeMount(demo_), x, true)).first;
        }
        return it->second;
    }
    const engine::SceneConfig& demo_;
    const engine::SceneConfig& stiff_;
    bool trajectories_;
    std::map<std::string, study::ExtremeRun> references_;
};

int main(int argc, char** argv) {
    bool quick = false, extremesOnly = false, scan = true, doExtremes = true, parallel = false, trajectories = true;
    int shard = 1, shards = 1;
    std::vector<int> extremeSizes;  // default: 33 and 65 (--quick: 33)
    std::string out = "out/study", exportDir, extremeScenePath = "flag_vehicle";
    std::vector<std::string> sceneFilter, solverSpecs, variantFilter, caseFilter, extraStiff;
    std::vector<int> sizeOverride;
    auto usageError = [](const std::string& why) {
        std::fprintf(stderr, "cloth_study: %s\n%s", why.c_str(), kUsage);
        return 2;
    };
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool hasValue = i + 1 < argc;
        if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            std::fputs(("\n--solvers takes these (" + std::string("name[:key=value,...]") + "):\n" + cloth::solverHelp()).c_str(), stdout);
            return 0;
        } else if (a == "--quick") quick = true;
        else if (a == "--extremes-only") extremesOnly = true;
        else if (a == "--no-scan") scan = false;
        else if (a == "--no-extremes") doExtremes = false;
        else if (a == "--no-trajectories") trajectories = false;
        else if (a == "--parallel") parallel = true;
        else if (a == "--export-newton" && hasValue) exportDir = argv[++i];
        else if (a == "--configs" && hasValue) variantFilter = split(argv[++i], ',');
        else if (a == "--cases" && hasValue) caseFilter = split(argv[++i], ',');
        else if (a == "--stiff-configs" && hasValue) extraStiff = split(argv[++i], ';');
        else if (a == "--extreme-scene" && hasValue) extremeScenePath = argv[++i];
        else if (a == "--shard" && hasValue) {
            const std::string v = argv[++i];
            if (std::sscanf(v.c_str(), "%d/%d", &shard, &shards) != 2 || shards < 1 || shards > 1000 || shard < 1 ||
                shard > shards || v.find_first_not_of("0123456789/") != std::string::npos)
                return usageError("--shard: '" + v + "' is not K/N with 1 <= K <= N <= 1000");
        } else if (a == "--extreme-sizes" && hasValue) {
            if (const std::string bad = readSides(a, argv[++i], 5, 257, extremeSizes); !bad.empty()) return usageError(bad);
        }
        else if (a == "--out" && hasValue) out = argv[++i];
        else if (a == "--scenes" && hasValue) {
            sceneFilter = split(argv[++i], ',');
            for (const std::string& sc : sceneFilter)
                if (sc != "hanging_flag" && sc != "vehicle_path") return usageError("--scenes: unknown scene '" + sc + "'");
        } else if (a == "--sizes" && hasValue) {
            if (const std::string bad = readSides(a, argv[++i], 3, 513, sizeOverride); !bad.empty()) return usageError(bad);
        } else if (a == "--solvers" && hasValue) {
            solverSpecs = split(argv[++i], ';');
            for (const std::string& spec : solverSpecs) {
                cloth::SolverConfig c;
                std::string error;
                if (!cloth::parseSolverConfig(spec, c, &error)) return usageError("--solvers: " + error);
            }
        } else return usageError("unknown or incomplete option '" + a + "'");
    }
    // The extreme cases' configurations (validated before any work starts).
    engine::SceneConfig demo;
    try {
        demo = engine::loadScene(engine::resolveScenePath(extremeScenePath, FLAGSIM_ASSETS_DIR));
    } catch (const std::exception& e) {
        return usageError(std::string("--extreme-scene: ") + e.what());
    }
    // The stiff scene's flag (flag_vehicle_stiff: the study's stiffness, multigrid, implicit air),
    // for the stiff_* configurations: the same cases with a flag ten times stiffer.
    engine::SceneConfig stiff;
    try {
        stiff = engine::loadScene(engine::resolveScenePath("flag_vehicle_stiff", FLAGSIM_ASSETS_DIR));
    } catch (const std::exception& e) {  // an installed tree missing the scene, or a bad edit of it
        std::fprintf(stderr, "cloth_study: the stiff_* configurations' scene: %s\n", e.what());
        return 1;
    }
    std::vector<Variant> variants = {{"reference", "", 1, -1, false, 0, 1},
                                     {"demo_default", demo.flag.solver.describe() + "|" + demo.flag.constraints.describe(), demo.flag.substeps},
                                     {"kangcho_1", "kangcho:iterations=1", 1},
                                     {"kangcho_1_substeps_4", "kangcho:iterations=1", 4},
                                     {"kangcho_1_strain_10pct", "kangcho:iterations=1|stretch_limit=0.1,stretch_passes=16", 1},
                                     {"kangcho_1_strain_10pct_substeps_4", "kangcho:iterations=1|stretch_limit=0.1,stretch_passes=16", 4},
                                     {"kangcho_2", "kangcho:iterations=2", 1},
                                     {"cg_5", "cg:iterations=5", 1},
                                     {"desbrun", "desbrun", 1},
                                     {"desbrun_strain_10pct", "desbrun|stretch_limit=0.1,stretch_passes=16", 1},
                                     {"explicit_10", "explicit:substeps=10", 1},
                                     {"kangcho_1_strain_10pct_implicit_air", "kangcho:iterations=1|stretch_limit=0.1,stretch_passes=16", 1, 1}};
    if (!quick)
        for (const Variant& v : std::vector<Variant>{{"multigrid", "multigrid", 1, 1},
                                                     {"multigrid_explicit_air", "multigrid", 1, 0},
                                                     {"multigrid_1_cycle", "multigrid:cycles=1", 1, 1}})
            variants.push_back(v);
    if (!quick) variants.push_back({"exact", "exact", 1});
    if (!quick) {  // the stiff flag: its reference (and at half the step), the scene's solver, the exact linearized step, newton
        const std::string stiffSolver = stiff.flag.solver.describe() + "|" + stiff.flag.constraints.describe();
        for (const Variant& v : std::vector<Variant>{
                 {"stiff_reference", "", 1, -1, true, 0, 1},
                 {"stiff_reference_half_step", "", 1, -1, true, 0, 2},
                 {"stiff_default", stiffSolver, stiff.flag.substeps, -1, true},
                 {"stiff_multigrid", "multigrid", 1, 1, true, 240},
                 {"stiff_exact", "exact:method=multigrid", 1, -1, true, 240},
                 {"stiff_newton_1", "newton:max_iterations=1", 1, -1, true, 240},
                 {"stiff_newton_be_240", "newton", 1, -1, true, 240},
                 {"stiff_newton_be_240_2", "newton:max_iterations=2", 1, -1, true, 240},
                 {"stiff_newton_bdf2_240_3", "newton:integrator=bdf2,max_iterations=3", 1, -1, true, 240},
                 {"stiff_newton_be_60", "newton", 1, -1, true, 60},
                 {"stiff_newton_bdf2_240", "newton:integrator=bdf2", 1, -1, true, 240},
                 {"stiff_newton_bdf2_120", "newton:integrator=bdf2", 1, -1, true, 120},
                 {"stiff_newton_bdf2_60", "newton:integrator=bdf2", 1, -1, true, 60},
                 {"stiff_newton_midpoint_60", "newton:integrator=midpoint", 1, -1, true, 60},
                 // the shipped step with fewer iterations allowed, or a looser stop
                 {"stiff_newton_bdf2_60_cap_4", "newton:integrator=bdf2,max_iterations=4", 1, -1, true, 60},
                 {"stiff_newton_bdf2_60_cap_5", "newton:integrator=bdf2,max_iterations=5", 1, -1, true, 60},
                 {"stiff_newton_bdf2_60_cap_6", "newton:integrator=bdf2,max_iterations=6", 1, -1, true, 60},
                 {"stiff_newton_bdf2_60_loose", "newton:integrator=bdf2,tolerance=0.01", 1, -1, true, 60},
                 // the converged BDF2 step in small steps: one per 960 Hz tick, or 240 Hz ticks of 2, 4 or
                 // 8 substeps, whose pins move along the carrier's path as the reference's do
                 {"stiff_newton_bdf2_960", "newton:integrator=bdf2", 1, -1, true, 960},
                 {"stiff_newton_bdf2_240x2", "newton:integrator=bdf2", 2, -1, true, 240},
                 {"stiff_newton_bdf2_240x4", "newton:integrator=bdf2", 4, -1, true, 240},
                 {"stiff_newton_bdf2_240x4_loose", "newton:integrator=bdf2,tolerance=0.01", 4, -1, true, 240},
                 {"stiff_newton_bdf2_240x8", "newton:integrator=bdf2", 8, -1, true, 240},
                 // the same steps with Newton capped at 1, 2 or 3 iterations, and the linearized
                 // symmetric step (the air's partial Jacobian) in steps of 1/960 s
                 {"stiff_newton_bdf2_240x4_1", "newton:integrator=bdf2,max_iterations=1", 4, -1, true, 240},
                 {"stiff_newton_bdf2_240x4_2", "newton:integrator=bdf2,max_iterations=2", 4, -1, true, 240},
                 {"stiff_newton_bdf2_240x4_3", "newton:integrator=bdf2,max_iterations=3", 4, -1, true, 240},
                 {"stiff_newton_bdf2_240x8_2", "newton:integrator=bdf2,max_iterations=2", 8, -1, true, 240},
                 {"stiff_newton_bdf2_240x8_3", "newton:integrator=bdf2,max_iterations=3", 8, -1, true, 240},
                 {"stiff_multigrid_240x4", "multigrid", 4, 1, true, 240},
                 // the air frozen at the step's start, its drag implicit in velocity; the springs converged
                 {"stiff_newton_be_240_frozen_air", "newton:air=frozen", 1, -1, true, 240},
                 {"stiff_newton_bdf2_240_frozen_air", "newton:integrator=bdf2,air=frozen", 1, -1, true, 240},
                 {"stiff_newton_bdf2_60_frozen_air", "newton:integrator=bdf2,air=frozen", 1, -1, true, 60},
                 // the springs as compliant constraints in small steps (XPBD), one pass or a few
                 {"stiff_xpbd_480", "xpbd", 1, -1, true, 480},
                 {"stiff_xpbd_960", "xpbd", 1, -1, true, 960},
                 {"stiff_xpbd_1920", "xpbd", 1, -1, true, 1920},
                 {"stiff_xpbd_3840", "xpbd", 1, -1, true, 3840},
                 {"stiff_xpbd_960_4", "xpbd:iterations=4", 1, -1, true, 960},
                 {"stiff_xpbd_960_16", "xpbd:iterations=16", 1, -1, true, 960},
                 {"stiff_xpbd_1920_4", "xpbd:iterations=4", 1, -1, true, 1920},
                 // the same with each row and column of structural springs solved at once
                 {"stiff_xpbd_chains_960", "xpbd:chains=on", 1, -1, true, 960},
                 {"stiff_xpbd_chains_1920", "xpbd:chains=on", 1, -1, true, 1920},
                 {"stiff_xpbd_chains_3840", "xpbd:chains=on", 1, -1, true, 3840}})
            variants.push_back(v);
    }
    for (const std::string& item : extraStiff) {  // NAME=SPEC@HZ or NAME=SPEC@HZxSUBSTEPS
        const std::size_t eq = item.find('='), at = item.rfind('@');
        cloth::SolverConfig c;
        std::string error;
        int hz = 0, substeps = 1;
        if (eq == std::string::npos || at == std::string::npos || at < eq || !parseRate(item.c_str() + at + 1, hz, substeps) ||
            !cloth::parseSolverConfig(item.substr(eq + 1, at - eq - 1), c, &error))
            return usageError("--stiff-configs: '" + item + "' is not NAME=SPEC@HZ or NAME=SPEC@HZxSUBSTEPS with a valid solver spec " + error);
        variants.push_back({item.substr(0, eq), item.substr(eq + 1, at - eq - 1), substeps, -1, true, hz});
    }
    std::vector<Extreme> cases = extremes();
    std::string unknown;
    if (!chooseByName(variants, variantFilter, unknown)) return usageError("--configs: unknown configuration '" + unknown + "'");
    if (!chooseByName(cases, caseFilter, unknown)) return usageError("--cases: unknown extreme case '" + unknown + "'");
    if (extremeSizes.empty()) extremeSizes = quick ? std::vector<int>{33} : std::vector<int>{33, 65};
    std::filesystem::create_directories(out);
    if (doExtremes && !extremeCasesDriveTheFlag(demo, exportDir.empty() ? out + "/extreme_cases.csv" : "")) return 1;
    const auto t0 = Clock::now();
    const double duration = quick ? 0.5 : 1.5;
    const PolePath path = drivePath(12.0);
    const Scene hanging{"hanging_flag", nullptr}, vehicle{"vehicle_path", &path};

    std::vector<Method> methods = {{"kangcho", "kangcho:iterations=1"}, {"kangcho", "kangcho:iterations=0"},
                                   {"kangcho", "kangcho:iterations=2"}, {"kangcho", "kangcho:iterations=3"},
                                   {"kangcho", "kangcho:iterations=4"}, {"kangcho", "kangcho:iterations=8"},
                                   {"kangcho", "kangcho:iterations=16"},
                                   {"kangcho_no_eq17", "kangcho:iterations=1,compression=off"},
                                   {"kangcho_no_eq17", "kangcho:iterations=4,compression=off"},
                                   {"exact", "exact"}, {"desbrun", "desbrun"},
                                   {"cg", "cg:iterations=2"}, {"cg", "cg:iterations=5"},
                                   {"cg", "cg:iterations=20"},
                                   {"chebyshev", "chebyshev:iterations=3"}, {"chebyshev", "chebyshev:iterations=8"},
                                   {"multigrid", "multigrid"}, {"multigrid", "multigrid:cycles=1"},
                                   {"multigrid", "multigrid:cycles=2"},
                                   {"multigrid_stationary", "multigrid", false, 1, stationaryCycles, "stationary"},
                                   {"explicit", "explicit:substeps=1"}, {"explicit", "explicit:substeps=10"},
                                   {"explicit", "explicit:substeps=100"}};
    methods.push_back({"bullet", "", true, 1});
    methods.push_back({"bullet", "", true, 10});
    if (!solverSpecs.empty()) {
        methods.clear();
        for (const std::string& spec : solverSpecs) methods.push_back({spec.substr(0, spec.find(':')), spec});
    }

    struct Config {
        const Scene* scene;
        int n;
        double k, h;
    };
    std::vector<Config> configs;
    const std::vector<int> sizes = !sizeOverride.empty() ? sizeOverride
                                   : quick             ? std::vector<int>{17, 33}
                                                       : std::vector<int>{17, 33, 65, 129};
    auto wanted = [&](const Scene* s) {
        return sceneFilter.empty() || std::find(sceneFilter.begin(), sceneFilter.end(), s->name) != sceneFilter.end();
    };
    for (const Scene* s : {&hanging, &vehicle})
        for (int n : sizes)
            if (wanted(s) && !(quick && sizeOverride.empty() && s == &vehicle && n > 17))
                configs.push_back({s, n, 1e4, 1.0 / 240});
    if (scan && wanted(&hanging))
        for (double k : quick ? std::vector<double>{1e1, 1e3, 1e5} : std::vector<double>{1e1, 1e2, 1e3, 1e4, 1e5, 1e6})
            for (double h : quick ? std::vector<double>{1.0 / 1000, 1.0 / 60, 1.0 / 15}
                                  : std::vector<double>{1.0 / 1000, 1.0 / 240, 1.0 / 60, 1.0 / 30, 1.0 / 15})
                if (!(k == 1e4 && h == 1.0 / 240)) configs.push_back({&hanging, 17, k, h});  // already above

    if (!exportDir.empty()) {
        std::filesystem::create_directories(exportDir);
        for (const Config& c : configs)
            if (!extremesOnly && c.k == 1e4 && c.h == 1.0 / 240) exportForNewton(exportDir, *c.scene, c.n, c.k, c.h, duration);
        if (doExtremes)  // --quick: the teleport only (the shortest case), to keep CI's run short
            for (const Extreme& x : cases)
                if (!quick || x.name == "teleport_1m")
                    for (const int size : extremeSizes) exportExtremeForNewton(exportDir, demo, x, size);
        std::fprintf(stderr, "flag and pole motion written to %s\n", exportDir.c_str());
        return 0;
    }
    if (extremesOnly) configs.clear();
    // Work items, in serial order: each part-1 configuration, then each extreme case x size x
    // configuration. A shard runs the items i with i % N == K - 1; every row carries its serial
    // number, so the shards' rows merge back into the serial run's order.
    long item = -1;
    auto mine = [&] { return ++item % shards == shard - 1; };
    const char* timing = parallel ? "parallel" : "serial";
    std::ofstream csv(out + (extremesOnly ? "/unused.csv" : "/error_vs_runtime.csv"));
    csv << "row,scene,size,stiffness,h,family,solver,ms_per_step,timing,solve_error,traj_error_be,traj_error_fine,"
           "max_stretch,p99_stretch,energy_growth,stable,fail_step\n";
    long row = -1;
    for (const Config& c : configs) {
        std::vector<Method> todo;  // the rows of this configuration
        for (const Method& method : methods) {
            if (method.bullet && c.scene->path) continue;  // Bullet's pins are fixed nodes
            if (c.n > 65 && method.spec == "explicit:substeps=100") continue;
            todo.push_back(method);
        }
        const long firstRow = row + 1;
        row += long(todo.size());
        if (!mine()) continue;
        // Above 65x65 the exact reference (a sparse Cholesky per step) would take most of the run:
        // 129x129 reports time, strain and stability, without trajectory errors.
        const bool big = c.n > 65;
        const auto ref = big ? std::vector<State>{} : referenceRun(*c.scene, c.n, c.k, c.h, duration);
        const bool fine = c.n == 17 && c.h >= 1.0 / 240 && (!quick || c.k == 1e4);
        std::vector<State> fineRef;
        if (fine) fineRef = referenceRun(*c.scene, c.n, c.k, c.h / 16, duration);
        for (std::size_t mi = 0; mi < todo.size(); ++mi) {
            // Above 65x65 the exact reference is multigrid to 1e-10 (Cholesky takes most of the run).
            Method m = todo[mi];
            if (big && m.spec == "exact") m.spec = "exact:method=multigrid";
            const Row r = runOne(*c.scene, c.n, c.k, c.h, m, duration, ref, fine, fineRef, 16);
            char line[600];
            std::snprintf(line, sizeof line, "%ld,%s,%d,%g,%g,%s,\"%s\",%.5g,%s,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%d,%d\n",
                          firstRow + long(mi), r.scene.c_str(), r.size, r.k, r.h, r.family.c_str(), r.solver.c_str(),
                          r.ms, timing, r.solveErr, r.trajBE, r.trajFine, r.maxStretch, r.p99Stretch, r.energyGrowth,
                          r.stable ? 1 : 0, r.failStep);
            csv << line;
        }
        std::fprintf(stderr, "\r%s %dx%d k=%g h=%g done (%.0f s)      ", c.scene->name.c_str(), c.n, c.n, c.k, c.h,
                     std::chrono::duration<double>(Clock::now() - t0).count());
    }
    csv.close();

    const long configRows = row + 1;
    if (!doExtremes) {
        writeShardInfo(out, shard, shards, configRows, 0);
        std::fprintf(stderr, "\nstudy done in %.0f s: %s/error_vs_runtime.csv\n",
                     std::chrono::duration<double>(Clock::now() - t0).count(), out.c_str());
        return 0;
    }
    // Part 2: the demo's flag through extreme carrier motions.
    std::ofstream ext(out + "/extreme.csv");
    // peak_stretch: max_stretch without the 0.25 s after a jump of the pole (teleport);
    // p99_stretch: the largest per-tick 99th percentile; late_max_stretch: the last second;
    // ke_*: kinetic energy in the carrier's frame; traj_error: against the flag's reference.
    ext << ExtremeStudy::header();
    ExtremeStudy study(demo, stiff, trajectories);
    row = -1;
    for (const Extreme& x : cases)
        for (const int size : extremeSizes)
            for (const Variant& v : variants) {
                ++row;
                if (mine()) ext << study.row(row, x, size, v, timing) << std::flush;
            }
    writeShardInfo(out, shard, shards, configRows, row + 1);
    std::fprintf(stderr, "\nstudy done in %.0f s: %s/error_vs_runtime.csv, %s/extreme.csv\n",
                 std::chrono::duration<double>(Clock::now() - t0).count(), out.c_str(), out.c_str());
    return 0;
}
