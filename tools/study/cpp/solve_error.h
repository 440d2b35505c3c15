#pragma once
// Part 1 of the study, the solve error (error_vs_runtime.csv): every solver on the same cloth,
// masses and pins, per scene (pole_paths.h), size, stiffness and time step, against the converged
// backward Euler step (the exact solve of the same linearized system). Metrics (words as in
// docs/algorithm.md):
//   ms_per_step          median over repeats in this process
//   solve_error          median |dv - dv_exact| / |dv_exact| over 24 states sampled along the run
//                        (implicit solvers; dv_exact: sparse Cholesky up to 65x65, multigrid to a
//                        relative residual of 1e-10 above)
//   traj_error_be        RMS distance to the converged backward Euler run (exact, same h), over
//                        0.25 s horizons restarted from states along that run, / cloth size
//   traj_error_fine      the same against exact backward Euler at h/16 (full run, small sizes)
//   max_stretch, p99_stretch over the run; energy_growth: max (E - E0) / (m g height)
//   stable, fail_step

#include <string>
#include <vector>

#include "pole_paths.h"
#include "progress.h"
#include "study_options.h"
#include "work_items.h"

namespace study {

// The scenes of part 1: the pole fixed, and carried along the demo's drive.
struct SolveErrorScenes {
    PolePath path = drivePath(12.0);
    Scene hanging{"hanging_flag", nullptr}, vehicle{"vehicle_path", &path};
};

// One configuration of part 1: a scene, a size, a stiffness and a step.
struct SolveErrorConfig {
    const Scene* scene;
    int n;
    double k, h;
};

// The configurations the options ask for, in the study's order.
std::vector<SolveErrorConfig> solveErrorConfigs(const StudyOptions& o, const SolveErrorScenes& scenes);

// The run's duration of each configuration (s).
inline double solveErrorDuration(const StudyOptions& o) { return o.quick ? 0.5 : 1.5; }

// Writes OUT/error_vs_runtime.csv (OUT/unused.csv with --front-only): the rows of the
// configurations this shard holds; returns the whole run's number of rows.
long runSolveError(const StudyOptions& o, const std::vector<SolveErrorConfig>& configs, WorkItems& work,
                   Progress& progress);
// The rows of part 1 that this shard runs; advances `work` past part 1's items.
long solveErrorRows(const StudyOptions& o, const std::vector<SolveErrorConfig>& configs, WorkItems& work);

}  // namespace study
