#pragma once
// One configuration of a flag through one path (extreme_cases.h, drive_case.h), as engine::Flag
// steps it, and what the study reports of the run; the fine-step reference that the
// configurations are judged against; and the short-horizon trajectory error against it.
//
// The reference is the same flag with the same model (springs, air, the pole's collisions, pins,
// and the flag's constraints) integrated by symplectic Euler in many substeps per tick, the air,
// the collisions and the constraints applied at every substep (engine::Flag's substeps). Its
// substeps per tick grow with the flag's resolution and with 1/sqrt(mass scale), as the highest
// spring frequency does, and with the pins' fastest move, so that the constraints keep up with a
// jump; the study runs it at twice as many too, and the docs hold its figures to change little
// when the step halves.
//
// Stable: finite and bounded throughout (positions within 100 m of the pole, speeds under
// 1000 m/s) and no failed cloth step. Stretch does not decide it: a soft
// flag may truly stretch a lot, and stretch beyond the reference's is error, judged by the
// bounds (docs/study.md).

#include <array>
#include <string>
#include <vector>

#include "cloth/model.h"
#include "engine/flag/flag.h"
#include "engine/scene/scene.h"
#include "extreme_cases.h"

namespace study {

// Patches per side of the patch energies: 8 is the study's judge (ke_patch_late), 4 and 16 show
// how its verdict depends on the patch size (ke_patch4_late, ke_patch16_late).
constexpr std::array<int, 3> kPatchCounts = {8, 4, 16};

struct ExtremeRun {
    bool stable = true;
    int failures = 0;
    std::string firstFailure;  // the cloth's description of its first failed tick (cloth.h), if any
    double msPerTick = 0;  // median
    // Median of the cloth's own profile per tick (air, solve, collisions, contact): a peer that
    // steps in another process (nvidia_newton_kind.cpp) reports its step's time there, without
    // the pipe's. Not kept by the references' cache.
    double msPerTickProfiled = 0;
    double maxStretch = 0, peakStretch = 0, p99Stretch = 0, lateStretch = 0, maxSpeed = 0;
    // The flag's kinetic energy in its carrier's frame, sum of m |v - v_carrier(x)|^2 / 2 (J): its
    // mean over the run, over the last second, and over each window of kEnergyWindow seconds.
    double energyMean = 0, energyLate = 0;
    std::vector<double> energyWindows;
    // The last second's mean of the same energy counted at the scale of P x P patches of the grid
    // (each patch's momentum), for each P of kPatchCounts: the flutter without the motion finer
    // than a patch.
    std::array<double, kPatchCounts.size()> patchEnergyLate{};
    double iterationsMean = 0;  // the solver's iterations per step (newton: Newton iterations)
    int iterationsMax = 0;
    // Crossings (cloth/crossings.h), counted after every tick: the most in one tick (edges through
    // the pole's solid, and edge-triangle pairs of the flag at least three cells apart), and the
    // ticks with any.
    int crossingsMax = 0, crossingTicks = 0;
    std::vector<cloth::State> states;  // the state after every tick, when kept (the reference)
};

constexpr double kEnergyWindow = 0.5;  // s
constexpr double kHorizon = 0.25;      // s: the restarts of the trajectory error

// The kinetic energy of state s of model m in carrier c's frame, sum of m |v - v_c(x)|^2 / 2 (J).
double carrierEnergy(const cloth::Model& m, const cloth::State& s, const engine::RigidFrame& c);

// The same energy at the scale of the grid's `patches` x `patches` patches (particle (col, r) in
// patch (col patches / nx, r patches / ny)): each patch's mass and momentum in c's frame, sum of
// |p|^2 / 2m. Motion inside a patch does not count, so at any resolution it measures the same
// physical flutter, without the grid-scale motion. NaN for a model that is not a grid of at least
// `patches` per side.
double patchEnergy(const cloth::Model& m, const cloth::State& s, const engine::RigidFrame& c, int patches);

// Runs scene `s`'s flag (its solver, constraints, substeps, air) on case x's carrier.
ExtremeRun runExtreme(const engine::SceneConfig& s, const engine::PoleMount& mount, const Extreme& x, bool keepStates);

// Substeps per tick of the reference for a flag of `size` per side in case x: `base` at 33 per
// side and mass scale 1, times size / 33 and 1 / sqrt(mass scale) (the explicit step's stability
// limit); and at least as many as keep every one of `pins` (carrier-frame points) within
// kReferencePinStep of where it was a substep before. A reference whose pins jump farther in a
// substep is not converged after a teleport: its tethers and stretch limit lag behind the pins
// (docs/study.md). No pins: the stability limit alone.
int referenceSubsteps(int base, int size, const Extreme& x, const std::vector<Eigen::Vector3d>& pins = {});
constexpr double kReferencePinStep = 0.01;  // m

// The reference ticks at this rate (states every 1/240 s), whatever the scene's.
constexpr double kReferenceHz = 240;

// Scene `s` made the reference: symplectic Euler, `substeps` per 240 Hz tick, with the flag's
// constraints (tethers, the stretch limit: part of its model) applied after every substep, or
// without them (`springsOnly`: the springs alone).
engine::SceneConfig referenceScene(engine::SceneConfig s, int substeps, bool springsOnly = false);

// The RMS distance to the reference, over horizons of kHorizon restarted from the reference's
// states, divided by the flag's width: how far the configuration drifts from the true motion in a
// quarter second. `reference`: a state every referenceH seconds, a whole fraction of the scene's
// tick. NaN when a restarted run fails or the ticks do not line up.
double horizonError(const engine::SceneConfig& s, const engine::PoleMount& mount, const Extreme& x,
                    const std::vector<cloth::State>& reference, double referenceH);

}  // namespace study
