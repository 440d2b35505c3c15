#include "configurations.h"

#include <cstdio>

#include "cloth/solver.h"

namespace study {

namespace {

// The demo's flag, in every run (demo_default, the scene's own, is added after the reference).
const Configuration kDemoConfigurations[] = {
    {.name = "reference", .referenceFactor = 1},
    {.name = "kangcho_1", .solver = "kangcho:iterations=1"},
    {.name = "kangcho_1_substeps_4", .solver = "kangcho:iterations=1", .substeps = 4},
    {.name = "kangcho_1_strain_10pct", .solver = "kangcho:iterations=1", .constraints = "stretch_limit=0.1,stretch_passes=16"},
    {.name = "kangcho_1_strain_10pct_substeps_4", .solver = "kangcho:iterations=1", .constraints = "stretch_limit=0.1,stretch_passes=16", .substeps = 4},
    {.name = "kangcho_2", .solver = "kangcho:iterations=2"},
    {.name = "cg_5", .solver = "cg:iterations=5"},
    {.name = "desbrun", .solver = "desbrun"},
    {.name = "desbrun_strain_10pct", .solver = "desbrun", .constraints = "stretch_limit=0.1,stretch_passes=16"},
    {.name = "explicit_10", .solver = "explicit:substeps=10"},
    {.name = "kangcho_1_strain_10pct_implicit_air", .solver = "kangcho:iterations=1", .constraints = "stretch_limit=0.1,stretch_passes=16", .implicitAir = 1},
};

// The demo's flag, in the full study: multigrid and the exact solve.
const Configuration kDemoFullConfigurations[] = {
    {.name = "multigrid", .solver = "multigrid", .implicitAir = 1},
    {.name = "multigrid_explicit_air", .solver = "multigrid", .implicitAir = 0},
    {.name = "multigrid_1_cycle", .solver = "multigrid:cycles=1", .implicitAir = 1},
    {.name = "exact", .solver = "exact"},
};

// The stiff flag, in the full study: its reference (and at half the step), the exact linearized
// step, newton, xpbd (stiff_default, the scene's own, is added after the references).
const Configuration kStiffConfigurations[] = {
    {.name = "stiff_reference", .stiff = true, .referenceFactor = 1},
    {.name = "stiff_reference_half_step", .stiff = true, .referenceFactor = 2},
    {.name = "stiff_multigrid", .solver = "multigrid", .implicitAir = 1, .stiff = true, .hz = 240},
    {.name = "stiff_exact", .solver = "exact:method=multigrid", .stiff = true, .hz = 240},
    {.name = "stiff_newton_1", .solver = "newton:max_iterations=1", .stiff = true, .hz = 240},
    {.name = "stiff_newton_be_240", .solver = "newton", .stiff = true, .hz = 240},
    {.name = "stiff_newton_be_240_2", .solver = "newton:max_iterations=2", .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240_3", .solver = "newton:integrator=bdf2,max_iterations=3", .stiff = true, .hz = 240},
    {.name = "stiff_newton_be_60", .solver = "newton", .stiff = true, .hz = 60},
    {.name = "stiff_newton_bdf2_240", .solver = "newton:integrator=bdf2", .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_120", .solver = "newton:integrator=bdf2", .stiff = true, .hz = 120},
    {.name = "stiff_newton_bdf2_60", .solver = "newton:integrator=bdf2", .stiff = true, .hz = 60},
    {.name = "stiff_newton_midpoint_60", .solver = "newton:integrator=midpoint", .stiff = true, .hz = 60},
    // the shipped step with fewer iterations allowed, or a looser stop
    {.name = "stiff_newton_bdf2_60_cap_4", .solver = "newton:integrator=bdf2,max_iterations=4", .stiff = true, .hz = 60},
    {.name = "stiff_newton_bdf2_60_cap_5", .solver = "newton:integrator=bdf2,max_iterations=5", .stiff = true, .hz = 60},
    {.name = "stiff_newton_bdf2_60_cap_6", .solver = "newton:integrator=bdf2,max_iterations=6", .stiff = true, .hz = 60},
    {.name = "stiff_newton_bdf2_60_loose", .solver = "newton:integrator=bdf2,tolerance=0.01", .stiff = true, .hz = 60},
    // the converged BDF2 step in small steps: one per 960 Hz tick, or 240 Hz ticks of 2, 4 or
    // 8 substeps, whose pins move along the carrier's path as the reference's do
    {.name = "stiff_newton_bdf2_960", .solver = "newton:integrator=bdf2", .stiff = true, .hz = 960},
    {.name = "stiff_newton_bdf2_240x2", .solver = "newton:integrator=bdf2", .substeps = 2, .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240x4", .solver = "newton:integrator=bdf2", .substeps = 4, .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240x4_loose", .solver = "newton:integrator=bdf2,tolerance=0.01", .substeps = 4, .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240x8", .solver = "newton:integrator=bdf2", .substeps = 8, .stiff = true, .hz = 240},
    // the same steps with Newton capped at 1, 2 or 3 iterations, and the linearized
    // symmetric step (the air's partial Jacobian) in steps of 1/960 s
    {.name = "stiff_newton_bdf2_240x4_1", .solver = "newton:integrator=bdf2,max_iterations=1", .substeps = 4, .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240x4_2", .solver = "newton:integrator=bdf2,max_iterations=2", .substeps = 4, .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240x4_3", .solver = "newton:integrator=bdf2,max_iterations=3", .substeps = 4, .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240x8_2", .solver = "newton:integrator=bdf2,max_iterations=2", .substeps = 8, .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240x8_3", .solver = "newton:integrator=bdf2,max_iterations=3", .substeps = 8, .stiff = true, .hz = 240},
    {.name = "stiff_multigrid_240x4", .solver = "multigrid", .substeps = 4, .implicitAir = 1, .stiff = true, .hz = 240},
    // the air frozen at the step's start, its drag implicit in velocity; the springs converged
    {.name = "stiff_newton_be_240_frozen_air", .solver = "newton:air=frozen", .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_240_frozen_air", .solver = "newton:integrator=bdf2,air=frozen", .stiff = true, .hz = 240},
    {.name = "stiff_newton_bdf2_60_frozen_air", .solver = "newton:integrator=bdf2,air=frozen", .stiff = true, .hz = 60},
    // the springs as compliant constraints in small steps (XPBD), one pass or a few
    {.name = "stiff_xpbd_480", .solver = "xpbd", .stiff = true, .hz = 480},
    {.name = "stiff_xpbd_960", .solver = "xpbd", .stiff = true, .hz = 960},
    {.name = "stiff_xpbd_1920", .solver = "xpbd", .stiff = true, .hz = 1920},
    {.name = "stiff_xpbd_3840", .solver = "xpbd", .stiff = true, .hz = 3840},
    {.name = "stiff_xpbd_960_4", .solver = "xpbd:iterations=4", .stiff = true, .hz = 960},
    {.name = "stiff_xpbd_960_16", .solver = "xpbd:iterations=16", .stiff = true, .hz = 960},
    {.name = "stiff_xpbd_1920_4", .solver = "xpbd:iterations=4", .stiff = true, .hz = 1920},
    // the same with each row and column of structural springs solved at once
    {.name = "stiff_xpbd_chains_960", .solver = "xpbd:chains=on", .stiff = true, .hz = 960},
    {.name = "stiff_xpbd_chains_1920", .solver = "xpbd:chains=on", .stiff = true, .hz = 1920},
    {.name = "stiff_xpbd_chains_3840", .solver = "xpbd:chains=on", .stiff = true, .hz = 3840},
};

// "HZ" or "HZxSUBSTEPS" (--stiff-configs): a physics rate, and the substeps of each of its ticks.
bool parseRate(const char* text, int& hz, int& substeps) {
    char rest = 0;
    substeps = 1;
    const int read = std::sscanf(text, "%dx%d%c", &hz, &substeps, &rest);
    if (read == 1 && std::sscanf(text, "%d%c", &hz, &rest) != 1) return false;  // "240x" or "240abc"
    return (read == 1 || read == 2) && hz > 0 && substeps > 0;
}

// The configurations of every run and of the full study, with each scene's own after the
// first reference.
std::vector<Configuration> tableOf(const StudyOptions& o, const engine::SceneConfig& demo, const engine::SceneConfig& stiff) {
    std::vector<Configuration> configs(std::begin(kDemoConfigurations), std::end(kDemoConfigurations));
    configs.insert(configs.begin() + 1, {.name = "demo_default", .solver = demo.flag.solver.describe(),
                                         .constraints = demo.flag.constraints.describe(), .substeps = demo.flag.substeps});
    if (o.quick) return configs;
    configs.insert(configs.end(), std::begin(kDemoFullConfigurations), std::end(kDemoFullConfigurations));
    const std::size_t firstStiff = configs.size();
    configs.insert(configs.end(), std::begin(kStiffConfigurations), std::end(kStiffConfigurations));
    configs.insert(configs.begin() + long(firstStiff) + 2,
                   {.name = "stiff_default", .solver = stiff.flag.solver.describe(),
                    .constraints = stiff.flag.constraints.describe(), .substeps = stiff.flag.substeps, .stiff = true});
    return configs;
}

// --stiff-configs' items: NAME=SPEC@HZ or NAME=SPEC@HZxSUBSTEPS, the stiff flag's.
bool addExtraStiff(const std::vector<std::string>& items, std::vector<Configuration>& configs, std::string* error) {
    for (const std::string& item : items) {
        const std::size_t eq = item.find('='), at = item.rfind('@');
        cloth::SolverConfig c;
        std::string why;
        int hz = 0, substeps = 1;
        if (eq == std::string::npos || at == std::string::npos || at < eq || !parseRate(item.c_str() + at + 1, hz, substeps) ||
            !cloth::parseSolverConfig(item.substr(eq + 1, at - eq - 1), c, &why)) {
            *error = "--stiff-configs: '" + item + "' is not NAME=SPEC@HZ or NAME=SPEC@HZxSUBSTEPS with a valid solver spec " + why;
            return false;
        }
        configs.push_back({.name = item.substr(0, eq), .solver = item.substr(eq + 1, at - eq - 1), .substeps = substeps,
                           .stiff = true, .hz = hz});
    }
    return true;
}

}  // namespace

std::vector<Configuration> configurations(const StudyOptions& o, const engine::SceneConfig& demo,
                                          const engine::SceneConfig& stiff, std::string* error) {
    std::vector<Configuration> configs = tableOf(o, demo, stiff);
    if (!addExtraStiff(o.extraStiff, configs, error)) return {};
    return configs;
}

}  // namespace study
