#include "configurations.h"

#include <algorithm>
#include <cstdio>

#include "cloth/solver.h"
#include "cloth/solver_config.h"

namespace study {

namespace {

constexpr FlagKind kDemo = FlagKind::Demo;

// The references and the shipped scenes.
const Configuration kReferences[] = {
    {.name = "reference", .referenceFactor = 1},
    {.name = "reference_half_step", .referenceFactor = 2, .maxSide = 33},
    // the demo's reference at its stability limit alone: after a teleport its constraints lag (docs/study.md)
    {.name = "reference_unpaced", .referenceFactor = 1, .paced = false, .flags = {kDemo}, .maxSide = 33},
    // the demo's flag without its tethers and stretch limit: the constraints' own effect
    {.name = "reference_springs", .referenceFactor = 1, .springsOnly = true, .flags = {kDemo}},
    {.name = "shipped", .shipped = true},
};

// The linearized implicit steps: the paper's step (with the flag's constraints, and without on
// the demo's flag), more Jacobi sweeps, Chebyshev, Desbrun, multigrid.
const Configuration kLinearized[] = {
    {.name = "kangcho", .solver = "kangcho"},
    {.name = "kangcho_float", .solver = "kangcho:precision=float"},
    {.name = "kangcho_no_constraints", .solver = "kangcho", .constraints = "", .flags = {kDemo}},
    {.name = "kangcho_3", .solver = "kangcho:iterations=3"},
    {.name = "kangcho_16", .solver = "kangcho:iterations=16"},
    {.name = "chebyshev_8", .solver = "chebyshev:iterations=8"},
    {.name = "desbrun", .solver = "desbrun"},
    {.name = "multigrid", .solver = "multigrid", .implicitAir = 1},
    {.name = "multigrid_1_cycle", .solver = "multigrid:cycles=1", .implicitAir = 1},
};

// The implicit step converged (newton): backward Euler and BDF2 at 60, 240 and 960 Hz (and BDF2
// at 1920 Hz), converged and capped at two iterations; steps shorter than a 240 Hz tick are its
// substeps, so the pins move along the carrier's path within the tick as the reference's do. At
// 65x65 the converged steps cost seconds per frame: the front runs the capped ones there.
const Configuration kConverged[] = {
    {.name = "newton_1", .solver = "newton:max_iterations=1"},
    {.name = "newton_be_60", .solver = "newton", .hz = 60, .maxSide = 33},
    {.name = "newton_be_240", .solver = "newton", .maxSide = 33},
    {.name = "newton_be_240_2", .solver = "newton:max_iterations=2"},
    {.name = "newton_be_960", .solver = "newton", .substeps = 4, .maxSide = 33},
    {.name = "newton_bdf2_60", .solver = "newton:integrator=bdf2", .hz = 60, .maxSide = 33},
    {.name = "newton_bdf2_60_2", .solver = "newton:integrator=bdf2,max_iterations=2", .hz = 60},
    {.name = "newton_bdf2_240", .solver = "newton:integrator=bdf2", .maxSide = 33},
    {.name = "newton_bdf2_240_2", .solver = "newton:integrator=bdf2,max_iterations=2"},
    {.name = "newton_bdf2_960", .solver = "newton:integrator=bdf2", .substeps = 4, .maxSide = 33},
    {.name = "newton_bdf2_960_2", .solver = "newton:integrator=bdf2,max_iterations=2", .substeps = 4},
    {.name = "newton_bdf2_1920", .solver = "newton:integrator=bdf2", .substeps = 8, .maxSide = 33},
    {.name = "newton_bdf2_1920_2", .solver = "newton:integrator=bdf2,max_iterations=2", .substeps = 8, .maxSide = 33},
};

// small_steps (the true motion's integrator in float SIMD): its substeps from the stability bound
// at fractions 1 (the default) and 1.2, and fixed counts, which lose the light particles (their
// stable step is ten times shorter). (Two threads give the same bits; the benchmark times them.)
const Configuration kTrueMotion[] = {
    {.name = "small_steps", .solver = "small_steps"},
    // and no pin or particle (relative to the pole) moving more than a centimetre in a substep
    {.name = "small_steps_paced", .solver = "small_steps:max_move=0.01"},
    {.name = "small_steps_f12", .solver = "small_steps:fraction=1.2"},
    {.name = "small_steps_64", .solver = "small_steps:substeps=64"},
    {.name = "small_steps_96", .solver = "small_steps:substeps=96"},
};

// The springs as compliant constraints (xpbd) at its useful rates and passes, and symplectic
// Euler at substep counts down to its stability limit (the air and collisions at every substep).
const Configuration kSmallSteps[] = {
    {.name = "xpbd_960", .solver = "xpbd", .substeps = 4},
    {.name = "xpbd_1920", .solver = "xpbd", .substeps = 8},
    {.name = "xpbd_3840", .solver = "xpbd", .substeps = 16},
    {.name = "xpbd_960_16", .solver = "xpbd:iterations=16", .substeps = 4},
    {.name = "xpbd_chains_1920", .solver = "xpbd:chains=on", .substeps = 8},
    {.name = "explicit_8", .solver = "explicit", .substeps = 8},
    {.name = "explicit_16", .solver = "explicit", .substeps = 16},
    {.name = "explicit_32", .solver = "explicit", .substeps = 32},
    {.name = "explicit_64", .solver = "explicit", .substeps = 64},
    {.name = "explicit_96", .solver = "explicit", .substeps = 96},
    {.name = "explicit_128", .solver = "explicit", .substeps = 128},
};

// Vertex Block Descent (vbd, Chen et al. 2024): per-vertex Newton steps on backward Euler's
// potential, color by color, with 10 passes at 240 Hz and with 5 at 960 Hz (the tick's substeps).
const Configuration kBlockDescent[] = {
    {.name = "vbd_10", .solver = "vbd"},
    {.name = "vbd_960_5", .solver = "vbd:iterations=5", .substeps = 4},
};

// Peers: Bullet's btSoftBody (bullet_kind.cpp) at 1 and 10 iterations of its position solver.
const Configuration kPeers[] = {
    {.name = "bullet_softbody_1", .solver = "bullet_softbody:iterations=1"},
    {.name = "bullet_softbody_10", .solver = "bullet_softbody:iterations=10"},
};

// With --nvidia-newton: NVIDIA Newton's solvers (nvidia_newton_kind.cpp) at their defaults, one
// Newton step per tick; XPBD in as many substeps of the tick as keep it stable by the harness's
// rule (flagstudy/nvidia_newton/solvers.py, auto_substeps: 30 for the demo's flag at 33x33; for the
// stiff flag's springs 3.1 times the demo's at 17x17, so 95), its air and pins moving at each.
const Configuration kNvidiaNewton[] = {
    {.name = "nvidia_newton_vbd", .solver = "nvidia_newton:method=vbd", .timing = "warp_cpu"},
    {.name = "nvidia_newton_xpbd_7200", .solver = "nvidia_newton:method=xpbd", .substeps = 30, .flags = {kDemo},
     .timing = "warp_cpu"},
    {.name = "nvidia_newton_xpbd_22800", .solver = "nvidia_newton:method=xpbd", .substeps = 95, .flags = {FlagKind::Stiff},
     .timing = "warp_cpu"},
    {.name = "nvidia_newton_style3d", .solver = "nvidia_newton:method=style3d", .timing = "warp_cpu"},
};

// With --contact: on the demo's flag, contact once per tick with half-space self bounds, in the true
// motion (instead of after each substep) and in the paper's step (instead of length bounds); on both
// flags, the true motion with contact after every second substep; on the stiff flag, after every
// fourth and every eighth; and each flag's stride only once the fastest particle has also moved so
// far relative to the pole since the last contact: the demo flag's every second substep and 1 cm
// (what the true-motion scene ships) or 2 cm, the stiff flag's every fourth and 2 cm (what the
// stiff scene ships).
const Configuration kContactPerTick[] = {
    {.name = "small_steps_paced_tick", .solver = "small_steps:max_move=0.01", .flags = {kDemo}, .contactStride = 0,
     .halfSpaces = true},
    {.name = "shipped_half_spaces", .shipped = true, .flags = {kDemo}, .contactStride = 0, .halfSpaces = true},
    {.name = "small_steps_paced_stride2", .solver = "small_steps:max_move=0.01", .contactStride = 2},
    {.name = "small_steps_paced_stride4", .solver = "small_steps:max_move=0.01", .flags = {FlagKind::Stiff}, .contactStride = 4},
    {.name = "small_steps_paced_stride8", .solver = "small_steps:max_move=0.01", .flags = {FlagKind::Stiff}, .contactStride = 8},
    {.name = "small_steps_paced_stride2_move2cm", .solver = "small_steps:max_move=0.01", .flags = {kDemo}, .contactStride = 2,
     .contactStrideMove = 0.02},
    {.name = "small_steps_paced_stride2_move1cm", .solver = "small_steps:max_move=0.01", .flags = {kDemo}, .contactStride = 2,
     .contactStrideMove = 0.01},
    {.name = "small_steps_paced_stride4_move2cm", .solver = "small_steps:max_move=0.01", .flags = {FlagKind::Stiff},
     .contactStride = 4, .contactStrideMove = 0.02},
};

// --quick: the reference, the shipped step (the paper's), the true motion in real time, and one
// configuration of each other family that costs little: the paper's step without the constraints,
// adaptive multigrid, capped BDF2 (with the air coupled), xpbd.
const char* const kQuick[] = {"reference", "shipped", "small_steps_paced", "kangcho_no_constraints", "multigrid",
                              "newton_bdf2_60_2", "xpbd_1920"};

// "HZ" or "HZxSUBSTEPS" (--add-configs): a physics rate, and the substeps of each of its ticks.
bool parseRate(const char* text, int& hz, int& substeps) {
    char rest = 0;
    substeps = 1;
    const int read = std::sscanf(text, "%dx%d%c", &hz, &substeps, &rest);
    if (read == 1 && std::sscanf(text, "%d%c", &hz, &rest) != 1) return false;  // "240x" or "240abc"
    return (read == 1 || read == 2) && hz > 0 && substeps > 0;
}

// --add-configs' items: NAME=SPEC@HZ or NAME=SPEC@HZxSUBSTEPS, on both flags.
bool addConfigs(const std::vector<std::string>& items, std::vector<Configuration>& configs, std::string* error) {
    for (const std::string& item : items) {
        const std::size_t eq = item.find('='), at = item.rfind('@');
        cloth::SolverConfig c;
        std::string why;
        int hz = 0, substeps = 1;
        if (eq == std::string::npos || at == std::string::npos || at < eq || !parseRate(item.c_str() + at + 1, hz, substeps) ||
            !cloth::parseSolverConfig(item.substr(eq + 1, at - eq - 1), c, &why)) {
            *error = "--add-configs: '" + item + "' is not NAME=SPEC@HZ or NAME=SPEC@HZxSUBSTEPS with a valid solver spec " + why;
            return false;
        }
        configs.push_back({.name = item.substr(0, eq), .solver = item.substr(eq + 1, at - eq - 1), .substeps = substeps,
                           .hz = hz});
    }
    return true;
}

}  // namespace

const char* flagName(FlagKind flag) { return flag == FlagKind::Demo ? "demo" : "stiff"; }

bool Configuration::runsOn(FlagKind flag, int side) const {
    return std::find(flags.begin(), flags.end(), flag) != flags.end() && (maxSide == 0 || side <= maxSide);
}

std::vector<Configuration> configurations(const StudyOptions& o, std::string* error) {
    std::vector<Configuration> all;
    all.insert(all.end(), std::begin(kReferences), std::end(kReferences));
    all.insert(all.end(), std::begin(kLinearized), std::end(kLinearized));
    all.insert(all.end(), std::begin(kConverged), std::end(kConverged));
    all.insert(all.end(), std::begin(kSmallSteps), std::end(kSmallSteps));
    all.insert(all.end(), std::begin(kTrueMotion), std::end(kTrueMotion));
    all.insert(all.end(), std::begin(kBlockDescent), std::end(kBlockDescent));
    all.insert(all.end(), std::begin(kPeers), std::end(kPeers));
    if (o.contact) all.insert(all.end(), std::begin(kContactPerTick), std::end(kContactPerTick));
    if (o.nvidiaNewton) all.insert(all.end(), std::begin(kNvidiaNewton), std::end(kNvidiaNewton));
    if (o.quick)
        std::erase_if(all, [](const Configuration& c) {
            return std::find_if(std::begin(kQuick), std::end(kQuick), [&](const char* q) { return c.name == q; }) ==
                   std::end(kQuick);
        });
    if (!addConfigs(o.extraConfigs, all, error)) return {};
    return all;
}

}  // namespace study
