#pragma once
// Solvers behind one small interface, chosen by name with parameters: "name[:key=value,...]".
// Every solver kind has its own settings struct and a table of its keys (name, type, range,
// default, one line of doc; cloth/src/solver_table.h). The string parser, the scene parser of the
// engine, validation, describe(), the --help text and the README's solver table all come from
// that table: `solverHelp()` prints it. The kinds:
//   kangcho    the paper: Jacobi iterations of the linearized backward Euler system
//   exact      the same system solved to a tolerance (sparse Cholesky, CG or multigrid)
//   cg         exact with method=cg
//   multigrid  V-cycles on the same system, as CG's preconditioner or alone
//   chebyshev  Jacobi with Chebyshev semi-iterative acceleration (Wang 2015)
//   desbrun    Desbrun, Schroder & Barr 1999: constant isotropic Jacobian, factored once
//   explicit   symplectic Euler with substeps
// Every kind takes strain_limit= and strain_passes= (Provot's anti-stretch pass after the step)
// and tether= (long-range attachments after the step, strain_limit.h), and every implicit kind
// compression= (eq. 17).
// A step never throws and never hands back a non-finite state: on failure the state is left as
// it was before the step and the status says why.

#include <memory>
#include <string>
#include <string_view>
#include <variant>

#include "cloth/strain_limit.h"
#include "cloth/system.h"

namespace cloth {

struct KangChoSettings {
    int iterations = 1;  // Jacobi sweeps after dv(0); 1 is the paper's step (eq. 14)
    // fast = the stencil layout when the springs form a few constant index offsets (grids), else
    // the per-particle gather; gather = always the latter; reference = the paper's step written
    // equation by equation (paper_step.cpp).
    enum class Impl { Fast, Gather, Reference };
    Impl impl = Impl::Fast;
    int threads = 1;               // worker threads (results identical for any count)
    bool singlePrecision = false;  // float arithmetic in the step (the state stays double)
};

struct ExactSettings {
    enum class Method { Cholesky, CG, Multigrid };
    Method method = Method::Cholesky;
    double tolerance = 1e-10;  // relative residual the solve must reach, or the step fails
    int maxIterations = 10000; // cg: iterations; multigrid: V-cycles
    // cg only: a fixed number of iterations, an approximation that never fails the step for not
    // converging (as kangcho:iterations=N); 0 = until the tolerance, within max_iterations.
    int iterations = 0;
};

struct MultigridSettings {
    int cycles = 0;            // fixed number of cycles; 0 = until the relative residual < tolerance
    double tolerance = 1.5e-3;
    int maxCycles = 16;        // cap of the adaptive mode
    // Adaptive: also stop only when no particle's Jacobi correction |W_ii^-1 r_i| exceeds this
    // fraction of the largest |dv_i| (0 = off). The relative residual is a mean over the cloth: a
    // wave front whose error sits on a few hundred particles passes it, and the error it leaves
    // there seeds a stretch spike a few steps later (docs/multigrid.md, "The stopping test").
    double localTolerance = 1e-2;
    int preSweeps = 1, postSweeps = 1;  // smoothing sweeps around each coarse correction
    double damping = 0.7;      // smoother: x += damping W_ii^-1 r
    enum class Coarsening { Auto, Geometric, Aggregation };
    Coarsening coarsening = Coarsening::Auto;  // Auto: geometric on grids, aggregation otherwise
    // Coarse operators: Galerkin P^T W P, or (grids only) the same cloth re-discretized on the
    // coarse grid: the same spring kernels at positions sampled from the finer level.
    enum class CoarseOperator { Galerkin, Rediscretized };
    CoarseOperator coarseOperator = CoarseOperator::Galerkin;
    // Galerkin on a grid: the coarse levels see each bend spring (i, i + 2) as two springs of
    // twice its stiffness block over its halves (i, i + 1) and (i + 1, i + 2), the same energy for
    // a displacement linear along the spring. The fine level keeps the true W (smoother, residual,
    // CG); only the coarse operators change, from a 25-point stencil to a 9-point one.
    bool collapseBend = true;
    // Coarse operators (and the coarsest factorization) rebuilt every this many solves, and
    // reused in between while the pinned particles, h and the Jacobian rule stay the same. The
    // finest level (smoother, residuals, CG) is always the current W, so an adaptive solve still
    // reaches its tolerance on the current system; only the coarse correction lags.
    int coarseEvery = 1;
    // Cycles as the preconditioner of conjugate gradients (one V-cycle per CG iteration) rather
    // than as a stationary iteration. The V-cycle is symmetric (the same damped Jacobi before and
    // after), so CG applies. Auto: CG, except for one fixed cycle, which CG would only scale by
    // its step length, at one product with W more (on the vehicle path that scaling moved the
    // solve error by -4% to +7%, and the cycle alone was 7-14% cheaper: docs/multigrid.md,
    // session 18). Float cycles always run under CG.
    enum class Krylov { Auto, CG, None };
    Krylov krylov = Krylov::Auto;
    bool conjugateGradients() const {
        return krylov == Krylov::CG || (krylov == Krylov::Auto && (cycles != 1 || floatCycles));
    }
    // Levels 1..kcycleLevels (not the coarsest) are solved, wherever a finer level calls them, by
    // two iterations of flexible CG each preconditioned by one cycle from that level (Notay and
    // Vassilevski's K-cycle), instead of one cycle. 0: a V-cycle. The preconditioner is then
    // nonlinear, and the outer CG uses the flexible (Polak-Ribiere) beta. -1 (auto): 1 when
    // adaptive (fewer, more accurate iterations for the same cost), 0 for a fixed count (whose
    // cost each K-cycle raises by 5-15%, and one K-cycle alone was not reliable: docs/multigrid.md).
    int kcycleLevels = -1;
    int kLevels() const { return kcycleLevels >= 0 ? kcycleLevels : cycles == 0 ? 1 : 0; }
    // Where each solve starts: from the last steps' dv (on the rows free now), or from zero.
    // Previous: the combination of the last startHistory solves' dv that minimizes the energy
    // norm of the error (one product with W per vector; zero is in their span, so after a jump
    // the coefficients fall to nearly nothing). Auto: previous when adaptive (the cycles to the
    // tolerance drop), zero for a fixed count (whose cost it would raise).
    enum class Start { Auto, Previous, Zero };
    Start start = Start::Auto;
    // Two vectors span the linear extrapolation 2 dv_{n-1} - dv_{n-2}: on the swung pole at
    // 129x129 the cycles per step fell from 5.47 (one vector) to 4.22, and three saved too
    // little for their extra product (docs/multigrid.md, session 18).
    int startHistory = 2;
    int threads = 1;
    bool singlePrecision = false;
    // Mixed precision (with singlePrecision false and conjugate gradients): the cycles, the
    // preconditioner, run on the same system rounded to float, while CG, its products with W and
    // the residual it tests stay double. A float cycle moves half the bytes of a double one; CG
    // corrects the preconditioner's rounding, so the solve still reaches double tolerances. Not
    // the default: with the local stopping test it holds the vehicle path as double cycles do,
    // but in the 10 g stop at 65x65 its peak stretch was higher in 4 of 5 runs (0.27-0.47 against
    // 0.16-0.36; docs/multigrid.md, session 17).
    bool floatCycles = false;
    int coarsestParticles = 16;  // coarsen until a level has at most this many (not a key)
    // The Galerkin product by stencil (nested grids, multigrid.h) from this many coarse points per
    // row; shorter rows use the plan, which was faster there with the bend springs kept (at 33x33:
    // 1.4x) and as fast with them collapsed. Not a key.
    int stencilGalerkinMinRow = 33;
};

struct ChebyshevSettings {
    int iterations = 1;
    double rho = 0;  // Jacobi spectral radius; 0 = estimated from the system each step
};

struct DesbrunSettings {};

struct ExplicitSettings {
    int substeps = 1;
};

struct SolverConfig {
    std::string name = "kangcho";
    bool compressionRule = true;  // implicit kinds: eq. 17 in the Jacobian
    double strainLimit = 0;       // any kind: Provot anti-stretch pass, max stretch (0 = off)
    int strainLimitPasses = 4;
    double tether = 0;            // any kind: long-range attachments, max stretch to the anchor (0 = off)
    std::variant<KangChoSettings, ExactSettings, MultigridSettings, ChebyshevSettings, DesbrunSettings,
                 ExplicitSettings>
        settings;
    // The settings of this config's kind (std::bad_variant_access for another kind).
    template <class S>
    const S& get() const { return std::get<S>(settings); }
    template <class S>
    S& get() { return std::get<S>(settings); }
    // "name:key=value,..." with the keys that differ from the kind's defaults (and those the
    // table always shows); parseSolverConfig reads it back to the same config.
    std::string describe() const;
};

// Parses "name[:key=value[,key=value...]]". Returns false and sets *error (naming the key and
// value) on an unknown name, unknown key or bad value.
bool parseSolverConfig(std::string_view spec, SolverConfig& out, std::string* error);
// The defaults of a kind (false and *error for an unknown name).
bool defaultSolverConfig(std::string_view name, SolverConfig& out, std::string* error);
// Sets one key from its text ("2", "1e-3", "on", "float"), with the same rules as the parser;
// on failure `config` is unchanged and *error names the key, the value and the allowed range.
bool setSolverParameter(SolverConfig& config, std::string_view key, std::string_view value, std::string* error);
// Checks a config's ranges; returns an empty string when valid, else what is wrong.
std::string validate(const SolverConfig& config);
// Every kind with its keys: plain text for --help, or a Markdown table for the README.
std::string solverHelp();
std::string solverTableMarkdown();

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
    // The worker threads of the kind's threads= setting (one thread: no workers). The step, its
    // post-step corrections and a caller's own per-step work (the engine's air) share them: two
    // pools would spin against each other on the same cores.
    ThreadPool& threadPool() const { return *pool_; }

protected:
    Solver() = default;  // solvers are made by makeSolver, which sets config_ first
    template <class S>
    const S& settings() const { return config_.get<S>(); }
    SolverConfig config_;
    StepProfile profile_;
    Points dv_;
    Tethers tethers_;  // config_.tether's anchors, kept while the pins stay the same
    std::shared_ptr<ThreadPool> pool_;

    template <class T>
    friend std::unique_ptr<Solver> createSolver(const SolverConfig& config);
};

// The threads= setting of the config's kind (1 for the kinds without one).
int threadsOf(const SolverConfig& config);

// A solver of class T holding `config` (used by the solver table's factories).
template <class T>
std::unique_ptr<Solver> createSolver(const SolverConfig& config) {
    std::unique_ptr<Solver> solver(new T());
    solver->config_ = config;
    solver->pool_ = std::make_shared<ThreadPool>(threadsOf(config));
    return solver;
}

// Returns null and sets *error for an invalid config.
std::unique_ptr<Solver> makeSolver(const SolverConfig& config, std::string* error = nullptr);

// The exact solution of the system: sparse Cholesky with iterative refinement. Returns false when
// the factorization fails or the relative residual stays over `tolerance`.
bool solveExact(const Model& model, const LinearSystem& sys, Points& dv, Scalar* residual = nullptr,
                Scalar tolerance = 1e-10);

// The paper's step (paper_step.cpp, kangcho's impl=reference): builds the system at `state`,
// then dv(0) and `iterations` Jacobi sweeps into dv.
void paperStep(const Model& model, const Environment& env, const State& state, const StepInput& input,
               bool compressionRule, int iterations, LinearSystem& sys, Points& dv);

// One Jacobi sweep: dvNext_i = W_ii^-1 (b_i + h^2 sum_j J_ij dv_j); pinned stay prescribed.
void jacobiSweep(const Model& model, const LinearSystem& sys, const Points& dv, Points& dvNext);
// dv(0)_i = W_ii^-1 b_i (eq. 11, k = 0); pinned get their prescribed dv.
void jacobiStart(const LinearSystem& sys, Points& dv);

}  // namespace cloth
