#pragma once
// The multigrid solver's settings (its keys: cycles, tolerance, max_cycles, threads, precision)
// and its tuning, which the study settled and which is not a key (docs/multigrid.md). Public,
// because the benchmark, the study and the tests set the tuning, and the multigrid hierarchy
// (cloth/src/multigrid/) reads both; the kind's keys and factory are in
// cloth/src/solvers/multigrid_solver.cpp. Filled in by code: `SolverConfig(MultigridSettings{.cycles = 2})`.

#include <optional>

namespace cloth {

// The multigrid's tuning: settled by the study (docs/multigrid.md, each choice with its CSV), so
// not a key. The benchmark, the study and the tests may set it; unset, a solver takes
// settledTuning() of its settings.
struct MultigridTuning {
    bool krylov = true;             // the cycles precondition CG; false: the cycles alone
    int kcycleLevels = 1;           // coarse levels 1..N are K-cycles; 0: V-cycles
    int startHistory = 2;           // start from the best combination of the last N solves' dv; 0: from zero
    double localTolerance = 1e-2;   // adaptive: also no particle's |W_ii^-1 r_i| above this times max |dv_i|
    int preSweeps = 1, postSweeps = 1;
    double damping = 0.7;           // smoother: x += damping W_ii^-1 r
    bool aggregation = false;       // smoothed aggregation on grids too (meshes always)
    int coarseEvery = 1;            // coarse operators rebuilt every this many solves
    int coarsestParticles = 16;     // coarsen until a level has at most this many
    int stencilGalerkinMinRow = 33; // the Galerkin product by stencil from this many coarse points per row
};

// The fields of the kind's keys, each documented once, in its key table (multigrid_solver.cpp;
// `flagsim --help` prints it).
struct MultigridSettings {
    static constexpr const char* kKind = "multigrid";
    int cycles = 0;
    double tolerance = 1.5e-3;
    int maxCycles = 16;
    int threads = 1;
    enum class Precision { Double, Mixed, Float };
    Precision precision = Precision::Double;
    std::optional<MultigridTuning> tuning = std::nullopt;  // not a key; unset: settledTuning(*this)
};

// The tuning the study settled for these settings: CG, except around one fixed cycle in double
// (which CG would only scale); when adaptive a K-cycle on level 1 and a start from the last two
// solves, for a fixed count V-cycles from zero.
MultigridTuning settledTuning(const MultigridSettings& settings);

}  // namespace cloth
