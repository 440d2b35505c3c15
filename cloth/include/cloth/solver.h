#pragma once
// Solvers behind one small interface, chosen by name with parameters:
//   kangcho   the paper: Jacobi iterations of the linearized backward Euler system
//             (iterations=1 by default, any k >= 0; compression=on|off for eq. 17;
//             threads=N, precision=double|float, impl=fast|gather|reference)
//   exact     the same system solved to a relative residual of 1e-10 (sparse Cholesky);
//             method=cg solves it with conjugate gradients (tolerance=, max_iterations=),
//             method=multigrid with multigrid V-cycles (O(n) per cycle; tolerance=,
//             max_iterations= caps the cycles)
//   cg        alias of exact with method=cg
//   multigrid V-cycles on the same system (multigrid.h): cycles=N (0 = adaptive: until the
//             relative residual is under tolerance=, at most max_cycles=), pre_sweeps=,
//             post_sweeps=, damping= (smoother), coarsening=auto|geometric|aggregation,
//             coarse=galerkin|rediscretize, krylov=cg|none (V-cycles as CG's preconditioner,
//             the default, or as the iteration itself),
//             threads=, precision=
//   explicit  symplectic Euler with substeps=N
//   desbrun   Desbrun, Schroder & Barr 1999: constant isotropic Jacobian, factored once
//   chebyshev Jacobi with Chebyshev semi-iterative acceleration (Wang 2015), iterations=N,
//             rho= (spectral radius estimate; 0 = estimate from the system each step)
// Any solver takes strain_limit=S (e.g. 0.1: springs at most 10% over rest length after the step,
// Provot 1995) and strain_passes=N.
// A step never throws and never hands back a non-finite state: on failure the state is left as
// it was before the step and the status says why.

#include <memory>
#include <string>
#include <string_view>

#include "cloth/system.h"

namespace cloth {

struct SolverConfig {
    std::string name = "kangcho";
    int iterations = 1;            // kangcho: Jacobi iterations after dv(0)
    bool compressionRule = true;   // eq. 17 in the Jacobian
    enum class Method { Cholesky, CG, Multigrid };
    Method method = Method::Cholesky;  // exact: how the system is solved
    Scalar tolerance = 1e-10;      // exact/cg: relative residual (multigrid: 1e-3 by default)
    int maxIterations = 10000;     // cg
    int substeps = 1;              // explicit
    int threads = 1;               // kangcho: worker threads (results identical for any count)
    bool singlePrecision = false;  // kangcho: float arithmetic in the step (state stays double)
    // kangcho implementation: fast = the stencil layout when the springs form a few constant index
    // offsets (grids; stencil_kangcho.h), else the per-particle gather (fast_kangcho.h); gather =
    // always the latter; reference = the straightforward per-spring 3x3 assembly.
    enum class Impl { Fast, Gather, Reference };
    Impl impl = Impl::Fast;
    Scalar rho = 0;                // chebyshev: Jacobi spectral radius; 0 = estimated each step
    int cycles = 0;                // multigrid: fixed V-cycles; 0 = adaptive (tolerance, maxCycles)
    int maxCycles = 16;            // multigrid: cap of the adaptive mode
    int preSweeps = 2, postSweeps = 2;  // multigrid: smoothing sweeps around each coarse correction
    Scalar damping = 0.7;          // multigrid: smoother x += damping W_ii^-1 r
    enum class Coarsening { Auto, Geometric, Aggregation };
    Coarsening coarsening = Coarsening::Auto;  // multigrid: auto = geometric on grids, else aggregation
    bool rediscretize = false;     // multigrid: coarse operators from a coarse cloth, not Galerkin
    bool krylov = true;            // multigrid: V-cycles precondition CG (krylov=cg) or iterate alone (none)
    Scalar strainLimit = 0;        // any solver: Provot anti-stretch pass, max stretch (0 = off)
    int strainLimitPasses = 4;
    std::string describe() const;  // "kangcho:iterations=1,compression=on"
};

// Parses "name[:key=value[,key=value...]]". Returns false and sets *error (naming the key and
// value) on an unknown name, unknown key or bad value.
bool parseSolverConfig(std::string_view spec, SolverConfig& out, std::string* error);
// Checks a config's ranges; returns an empty string when valid, else what is wrong.
std::string validate(const SolverConfig& config);

enum class StepStatus { Ok, NonFinite, SolverFailed };
const char* toString(StepStatus status);

struct StepResult {
    StepStatus status = StepStatus::Ok;
    Index badParticle = -1;  // first particle with a non-finite position or velocity
    int iterations = 0;      // solver iterations used (CG, Jacobi, multigrid V-cycles)
    Scalar residual = -1;    // relative residual of the linear solve; -1 where not computed
};

// Milliseconds spent in each phase of the last step.
struct StepProfile {
    double forcesMs = 0;     // forces and Jacobian blocks
    double solveMs = 0;      // the linear solve (or explicit substeps)
    double integrateMs = 0;  // update of x and v, pins, finiteness check
};

class Solver {
public:
    virtual ~Solver() = default;
    virtual StepResult step(const Model& model, const Environment& env, State& state,
                            const StepInput& input) = 0;
    const SolverConfig& config() const { return config_; }
    const StepProfile& profile() const { return profile_; }
    // dv of the last step (implicit solvers), for solve-error diagnostics.
    const Points& lastDv() const { return dv_; }
    // What the solver chose at run time, if anything (multigrid: its levels), for logs.
    virtual std::string details() const { return {}; }

    explicit Solver(SolverConfig config) : config_(std::move(config)) {}

protected:
    SolverConfig config_;
    StepProfile profile_;
    Points dv_;
};

// Returns null and sets *error for an invalid config.
std::unique_ptr<Solver> makeSolver(const SolverConfig& config, std::string* error = nullptr);

// The exact solution of the system (Cholesky, refined to a relative residual <= 1e-10).
// Returns false when the factorization fails.
bool solveExact(const Model& model, const LinearSystem& sys, Points& dv, Scalar* residual = nullptr);

// One Jacobi sweep: dvNext_i = W_ii^-1 (b_i + h^2 sum_j J_ij dv_j); pinned stay prescribed.
void jacobiSweep(const Model& model, const LinearSystem& sys, const Points& dv, Points& dvNext);
// dv(0)_i = W_ii^-1 b_i (eq. 11, k = 0); pinned get their prescribed dv.
void jacobiStart(const LinearSystem& sys, Points& dv);

}  // namespace cloth
