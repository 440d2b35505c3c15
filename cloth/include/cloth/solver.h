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
//   newton     the implicit step converged (backward Euler or BDF2), the air fully coupled
//   xpbd       the springs as compliant constraints (XPBD, Macklin et al. 2016), projected
// Every implicit kind takes compression= (eq. 17). The corrections after a step (tethers, the
// stretch limit) are the cloth's constraints, not a solver's keys: Solver::setConstraints
// (constraints.h).
// A step never throws and never hands back a non-finite state: on failure the state is left as
// it was before the step and the status says why.

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "cloth/constraints.h"
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

struct MultigridSettings {
    int cycles = 0;             // fixed number of cycles; 0 = until the tolerance, within maxCycles
    double tolerance = 1.5e-3;  // adaptive: relative residual to reach
    int maxCycles = 16;
    int threads = 1;
    // double; mixed: float cycles preconditioning a double CG; float: all in float
    enum class Precision { Double, Mixed, Float };
    Precision precision = Precision::Double;
    std::optional<MultigridTuning> tuning;  // unset: settledTuning(*this)
};

// The tuning the study settled for these settings: CG, except around one fixed cycle in double
// (which CG would only scale); when adaptive a K-cycle on level 1 and a start from the last two
// solves, for a fixed count V-cycles from zero.
MultigridTuning settledTuning(const MultigridSettings& settings);

struct ChebyshevSettings {
    int iterations = 1;
    double rho = 0;  // Jacobi spectral radius; 0 = estimated from the system each step
};

struct DesbrunSettings {};

struct ExplicitSettings {
    int substeps = 1;
};

// newton: the implicit step solved to convergence (nonlinear/newton.h): Newton iterations on the
// step's equations, each a GMRES solve preconditioned by the multigrid hierarchy, with the air
// fully coupled (its position and velocity derivatives, evaluated at the new state).
struct NewtonSettings {
    // be: backward Euler; bdf2: BDF2; midpoint: the theta-midpoint rule (theta = 1/2: implicit
    // midpoint, which damps no mode; theta = 1: backward Euler)
    enum class Integrator { BackwardEuler, BDF2, Midpoint };
    Integrator integrator = Integrator::BackwardEuler;
    double theta = 0.5;             // midpoint: where in the step the forces are taken
    int maxIterations = 8;          // Newton iterations per step; 1 = the linearized step
    double tolerance = 1e-3;        // stop when the last iteration changed no velocity by more, m/s
    double linearTolerance = 1e-2;  // relative residual of each iteration's linear solve
    // coupled: the air evaluated at every iterate with its whole derivative; frozen: the air at
    // the step's start (the caller's external force), its drag implicit in velocity as the other
    // implicit solvers take it (StepInput::damping)
    bool coupledAir = true;
    int threads = 1;
};

// xpbd: each spring a compliant distance constraint (compliance 1/k: the same energy), projected
// by Gauss-Seidel after an unconstrained prediction; run in small steps (the scene's substeps or
// physics rate), one iteration per step (Macklin et al. 2019).
struct XpbdSettings {
    int iterations = 1;  // passes over the springs per step
    bool chains = false;  // a grid's rows and columns of structural springs each solved at once
};

struct SolverConfig {
    std::string name = "kangcho";
    bool compressionRule = true;  // implicit kinds: eq. 17 in the Jacobian
    std::variant<KangChoSettings, ExactSettings, MultigridSettings, ChebyshevSettings, DesbrunSettings,
                 ExplicitSettings, NewtonSettings, XpbdSettings>
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
// The solver table as data for a user interface (the demo's panel): the kinds, and each key of a
// config's kind with its row and its value.
struct SolverKeyInfo {
    enum class Type { Integer, Real, Choice };
    std::string name, doc;
    Type type = Type::Integer;
    std::string range;                 // "[0, 100000]", "fast|gather|reference"
    std::vector<std::string> choices;  // Choice: the allowed words
    double value = 0;                  // Choice: the index of the word
};
std::vector<std::string> solverKindNames();
std::vector<SolverKeyInfo> solverKeys(const SolverConfig& config);
// Every kind with its keys: plain text for --help, or a Markdown table for the README.
std::string solverHelp();
std::string solverTableMarkdown();

enum class StepStatus { Ok, NonFinite, SolverFailed };
const char* toString(StepStatus status);

struct StepResult {
    StepStatus status = StepStatus::Ok;
    Index badParticle = -1;  // first particle with a non-finite position or velocity
    int iterations = 0;      // solver iterations used (CG, Jacobi, multigrid V-cycles; newton: Newton iterations)
    Scalar residual = -1;    // relative residual of the linear solve (newton: max |R_i| / m_i); -1 where not computed
    int linearIterations = 0;  // newton: the GMRES iterations of all its linear solves
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
    // The cloth's constraints, applied after each step (none by default).
    void setConstraints(const Constraints& constraints) { constraints_.set(constraints); }
    const Constraints& constraints() const { return constraints_.settings(); }
    const StepProfile& profile() const { return profile_; }
    // dv of the last step (implicit solvers), for solve-error diagnostics.
    const Points& lastDv() const { return dv_; }
    // What the solver chose at run time, if anything (multigrid: its levels), for logs.
    virtual std::string details() const { return {}; }
    // Whether the solver evaluates the air itself at the end-of-step state (StepInput::air).
    virtual bool couplesAir() const { return false; }
    // Forget what the solver keeps from earlier steps (BDF2's last state): the next step starts
    // afresh. The caller calls it when it moves the cloth to a state the solver did not make.
    virtual void resetHistory() {}
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
    ConstraintSet constraints_;  // with their workspaces (the tethers' anchors, the stretch limit's checks)
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
void paperStep(const StepProblem& problem, int iterations, LinearSystem& sys, Points& dv);

// One Jacobi sweep: dvNext_i = W_ii^-1 (b_i + h^2 sum_j J_ij dv_j); pinned stay prescribed.
void jacobiSweep(const Model& model, const LinearSystem& sys, const Points& dv, Points& dvNext);
// dv(0)_i = W_ii^-1 b_i (eq. 11, k = 0); pinned get their prescribed dv.
void jacobiStart(const LinearSystem& sys, Points& dv);

}  // namespace cloth
