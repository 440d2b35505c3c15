#include "solve_error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include "cloth/solver_config.h"
#include "cloth/diagnostics.h"
#include "peers/bullet_cloth.h"
#include "specs.h"

namespace study {

namespace {

using Clock = std::chrono::steady_clock;
using cloth::Points;
using cloth::State;

// One stepping method: a cloth::Solver by spec, or Bullet's btSoftBody.
struct Method {
    std::string family, spec;
    bool bullet = false;
    int bulletIterations = 1;
    void (*tune)(cloth::MultigridTuning&) = nullptr;  // multigrid: its settled tuning changed
    std::string tuning = {};  // the tuning's name, after the spec in the row's label: "multigrid/stationary"
};

void stationaryCycles(cloth::MultigridTuning& t) { t.krylov = false; }

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

// The methods of each configuration: every solver family, or the --solvers specs.
std::vector<Method> methodsOf(const StudyOptions& o) {
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
    if (!o.solverSpecs.empty()) {
        methods.clear();
        for (const std::string& spec : o.solverSpecs) methods.push_back({spec.substr(0, spec.find(':')), spec});
    }

    return methods;
}

// The rows of one configuration (Bullet's pins are fixed nodes: not on the moving pole; 100
// explicit substeps are not run above 65x65).
std::vector<Method> methodsFor(const SolveErrorConfig& c, const std::vector<Method>& methods) {
    std::vector<Method> todo;
    for (const Method& method : methods) {
        if (method.bullet && c.scene->path) continue;
        if (c.n > 65 && method.spec == "explicit:substeps=100") continue;
        todo.push_back(method);
    }
    return todo;
}

// One configuration's rows into `csv`, numbered from firstRow.
void runConfig(const StudyOptions& o, const SolveErrorConfig& c, const std::vector<Method>& todo, long firstRow,
               std::ofstream& csv) {
    const double duration = solveErrorDuration(o);
    // Above 65x65 the exact reference (a sparse Cholesky per step) would take most of the run:
    // 129x129 reports time, strain and stability, without trajectory errors.
    const bool big = c.n > 65;
    const auto ref = big ? std::vector<State>{} : referenceRun(*c.scene, c.n, c.k, c.h, duration);
    const bool fine = c.n == 17 && c.h >= 1.0 / 240 && (!o.quick || c.k == 1e4);
    std::vector<State> fineRef;
    if (fine) fineRef = referenceRun(*c.scene, c.n, c.k, c.h / 16, duration);
    const char* timing = o.parallel ? "parallel" : "serial";
    for (std::size_t mi = 0; mi < todo.size(); ++mi) {
        // Above 65x65 the exact reference is multigrid to 1e-10 (Cholesky takes most of the run).
        Method m = todo[mi];
        if (big && m.spec == "exact") m.spec = "exact:method=multigrid";
        const Row r = runOne(*c.scene, c.n, c.k, c.h, m, duration, ref, fine, fineRef, 16);
        char line[600];
        std::snprintf(line, sizeof line, "%ld,%s,%d,%g,%g,%g,%s,\"%s\",%.5g,%s,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%d,%d\n",
                      firstRow + long(mi), r.scene.c_str(), r.size, r.k, r.h, duration, r.family.c_str(), r.solver.c_str(),
                      r.ms, timing, r.solveErr, r.trajBE, r.trajFine, r.maxStretch, r.p99Stretch, r.energyGrowth,
                      r.stable ? 1 : 0, r.failStep);
        csv << line;
    }
}

}  // namespace

std::vector<SolveErrorConfig> solveErrorConfigs(const StudyOptions& o, const SolveErrorScenes& scenes) {
    std::vector<SolveErrorConfig> configs;
    const std::vector<int> sizes = !o.sizeOverride.empty() ? o.sizeOverride
                                   : o.quick               ? std::vector<int>{17}
                                                           : std::vector<int>{17, 33, 65, 129};
    auto wanted = [&](const Scene* s) {
        return o.sceneFilter.empty() || std::find(o.sceneFilter.begin(), o.sceneFilter.end(), s->name) != o.sceneFilter.end();
    };
    const Scene* hanging = &scenes.hanging;
    const Scene* vehicle = &scenes.vehicle;
    for (const Scene* s : {hanging, vehicle})
        for (int n : sizes)
            if (wanted(s) && !(o.quick && o.sizeOverride.empty() && s == vehicle && n > 17))
                configs.push_back({s, n, 1e4, 1.0 / 240});
    if (o.scan && wanted(hanging))
        for (double k : o.quick ? std::vector<double>{1e1, 1e3, 1e5} : std::vector<double>{1e1, 1e2, 1e3, 1e4, 1e5, 1e6})
            for (double h : o.quick ? std::vector<double>{1.0 / 60, 1.0 / 15}
                                    : std::vector<double>{1.0 / 1000, 1.0 / 240, 1.0 / 60, 1.0 / 30, 1.0 / 15})
                if (!(k == 1e4 && h == 1.0 / 240)) configs.push_back({hanging, 17, k, h});  // already above
    return configs;
}

long solveErrorRows(const StudyOptions& o, const std::vector<SolveErrorConfig>& configs, WorkItems& work) {
    const std::vector<Method> methods = methodsOf(o);
    long mine = 0;
    for (const SolveErrorConfig& c : configs) {
        const long rows = long(methodsFor(c, methods).size());
        if (work.mine()) mine += rows;
    }
    return mine;
}

long runSolveError(const StudyOptions& o, const std::vector<SolveErrorConfig>& configs, WorkItems& work,
                   Progress& progress) {
    const std::vector<Method> methods = methodsOf(o);
    std::ofstream csv(o.out + (o.frontOnly ? "/unused.csv" : "/error_vs_runtime.csv"));
    csv << "row,scene,size,stiffness,h,duration,family,solver,ms_per_step,timing,solve_error,traj_error_be,traj_error_fine,"
           "max_stretch,p99_stretch,energy_growth,stable,fail_step\n";
    long row = -1;
    for (const SolveErrorConfig& c : configs) {
        const std::vector<Method> todo = methodsFor(c, methods);
        const long firstRow = row + 1;
        row += long(todo.size());
        if (!work.mine()) continue;
        char what[160];
        std::snprintf(what, sizeof what, "solve error: %s %dx%d k=%g h=%g, %zu solvers", c.scene->name.c_str(), c.n, c.n,
                      c.k, c.h, todo.size());
        progress.begin(what);
        const auto t0 = Clock::now();
        runConfig(o, c, todo, firstRow, csv);
        progress.done(long(todo.size()), what, clockText(std::chrono::duration<double>(Clock::now() - t0).count()));
    }
    return row + 1;
}

}  // namespace study
