// cloth_run: steps a named cloth scene headlessly with a chosen solver and prints steps per
// second and the diagnostics. The cloth library's own main job; needs nothing but Eigen.
//
//   cloth_run --scene hanging_flag --solver kangcho:iterations=1 --steps 600

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "cloth/diagnostics.h"
#include "cloth/presets.h"
#include "cloth/solver.h"
#include "cloth/solver_config.h"

namespace {

struct Options {
    std::string scene = "hanging_flag";
    std::string solver = "kangcho";
    std::string constraints;
    int steps = 600;
    int nx = 33, ny = 33;
    double stiffness = 1e4;
    double dt = 1.0 / 60;
    int repeats = 5;
    int errorEvery = 0;
};

// What the repeats measured.
struct Result {
    std::vector<double> stepsPerSecond;
    cloth::Diagnostics diag;
    const char* unstable = nullptr;
    double maxSolveError = 0;
    std::string details;
    long long iterations = 0;
};

// One timed repeat from rest (the first also counts iterations and the solve error); false when a
// step fails.
bool runRepeat(const Options& o, const cloth::SolverConfig& config, const cloth::Constraints& constraints,
               const cloth::HangingFlagDesc& desc, int rep, Result& out) {
    cloth::HangingFlag flag = cloth::makeHangingFlag(desc);
    auto solver = cloth::makeSolver(config);
    solver->setConstraints(constraints);
    cloth::Environment env;
    cloth::StepInput input;
    input.h = o.dt;
    input.pins = flag.pins;
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < o.steps; ++s) {
        const bool measureError = rep == 0 && o.errorEvery > 0 && s % o.errorEvery == 0;
        cloth::State before;
        if (measureError) before = flag.state;
        const cloth::StepResult r = solver->step(flag.model, env, flag.state, input);
        if (r.status != cloth::StepStatus::Ok) {
            std::printf("step %d failed: %s (particle %d); state kept at the last good step\n", s,
                        cloth::toString(r.status), r.badParticle);
            return false;
        }
        if (rep == 0) out.iterations += r.iterations;
        if (measureError)
            out.maxSolveError = std::max(
                out.maxSolveError, cloth::solveError({flag.model, env, before, input, config.compressionRule}, solver->lastDv()));
    }
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.stepsPerSecond.push_back(o.steps / sec);
    out.details = solver->details();
    out.diag = cloth::measure(flag.model, env, flag.state);
    out.unstable = cloth::instability(out.diag, flag.state, desc.poleTop);
    return true;
}

void report(const Options& o, const cloth::SolverConfig& config, const cloth::Constraints& constraints, Result& r) {
    std::sort(r.stepsPerSecond.begin(), r.stepsPerSecond.end());
    const double median = r.stepsPerSecond[r.stepsPerSecond.size() / 2];
    std::printf("scene            %s %dx%d, k=%g N/m, h=%g s, %d steps x %d repeats\n", o.scene.c_str(), o.nx, o.ny,
                o.stiffness, o.dt, o.steps, o.repeats);
    std::printf("solver           %s\n", describe(config).c_str());
    if (constraints.any()) std::printf("constraints      %s\n", constraints.describe().c_str());
    if (!r.details.empty()) std::printf("                 %s\n", r.details.c_str());
    std::printf("iterations       %.2f per step (mean)\n", double(r.iterations) / o.steps);
    std::printf("steps/s          %.1f (median; %.2f us/step)\n", median, 1e6 / median);
    std::printf("stretch          max %.4f  p99 %.4f\n", r.diag.maxStretch, r.diag.p99Stretch);
    std::printf("compression      max %.4f  p99 %.4f\n", r.diag.maxCompression, r.diag.p99Compression);
    std::printf("energy           kinetic %.6g J  potential %.6g J\n", r.diag.kinetic, r.diag.potential);
    std::printf("stable           %s\n", r.unstable ? r.unstable : "yes");
    if (o.errorEvery > 0) std::printf("solve error      max %.3e\n", r.maxSolveError);
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{"Steps a cloth scene headlessly and prints steps/s and diagnostics."};
    app.add_option("--scene", o.scene, "scene name")->check(CLI::IsMember({"hanging_flag"}));
    app.add_option("--solver", o.solver,
                   "solver spec name[:key=value,...], e.g. multigrid:cycles=2 (every solver and key below)");
    app.add_option("--constraints", o.constraints,
                   "the cloth's constraints key=value,..., e.g. tether=0.02,stretch_limit=0.1 (keys below)");
    app.add_option("--steps", o.steps, "steps per repeat")->check(CLI::Range(1, 10000000));
    app.add_option("--nx", o.nx, "particles across")->check(CLI::Range(2, 1024));
    app.add_option("--ny", o.ny, "particles down")->check(CLI::Range(2, 1024));
    app.add_option("--stiffness", o.stiffness, "structural and shear stiffness, N/m (bend: /10)")
        ->check(CLI::PositiveNumber);
    app.add_option("--dt", o.dt, "time step, s")->check(CLI::Range(1e-6, 1.0));
    app.add_option("--repeats", o.repeats, "timed repeats (median reported)")->check(CLI::Range(1, 1000));
    app.add_option("--solve-error-every", o.errorEvery,
                   "measure the solve error against the exact solve every N steps (0: never)")
        ->check(CLI::Range(0, 10000000));
    bool solverTable = false;
    app.add_flag("--solver-table", solverTable, "print the solver table as Markdown (the README's) and exit");
    app.footer(cloth::solverHelp());
    CLI11_PARSE(app, argc, argv);
    if (solverTable) {
        std::cout << cloth::solverTableMarkdown();
        return 0;
    }

    cloth::SolverConfig config;
    std::string error;
    if (!cloth::parseSolverConfig(o.solver, config, &error)) {
        std::cerr << "cloth_run: --solver " << o.solver << ": " << error << "\n";
        return 2;
    }
    cloth::Constraints constraints;
    if (!cloth::parseConstraints(o.constraints, constraints, &error)) {
        std::cerr << "cloth_run: --constraints " << o.constraints << ": " << error << "\n";
        return 2;
    }
    cloth::HangingFlagDesc desc;
    desc.nx = o.nx;
    desc.ny = o.ny;
    desc.stiffness = {o.stiffness, o.stiffness, o.stiffness / 10};

    Result result;
    for (int rep = 0; rep < o.repeats; ++rep)
        if (!runRepeat(o, config, constraints, desc, rep, result)) return 1;
    report(o, config, constraints, result);
    return result.unstable ? 1 : 0;
}
