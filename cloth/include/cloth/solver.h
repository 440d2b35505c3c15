#pragma once
// Solvers behind one small interface, chosen by name with parameters: "name[:key=value,...]".
// Every solver kind has its own file with its settings struct, a table of its keys (name, type,
// range, default, one line of doc) and its factory, registered in the solver registry
// (cloth/src/registry/solver_registry.h). The string parser, the scene parser of the engine,
// validation, describe(), the --help text, the README's solver table and the demo's panel all
// come from that registry: `solverHelp()` prints it. The kinds:
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

#include <any>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cloth/constraints.h"
#include "cloth/system.h"

namespace cloth {

struct SolverConfig {
    SolverConfig();  // the paper's step: kangcho at its defaults
    std::string name = "kangcho";
    bool compressionRule = true;  // implicit kinds: eq. 17 in the Jacobian
    // The settings struct of the config's kind (each kind declares its own, in its file).
    std::any settings;
    // The settings of this config's kind (std::bad_any_cast for another kind's).
    template <class S>
    const S& get() const { return std::any_cast<const S&>(settings); }
    template <class S>
    S& get() { return std::any_cast<S&>(settings); }
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
    // Whether the solver meets the colliders itself, at every substep (StepInput::colliders).
    virtual bool resolvesCollisions() const { return false; }
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

// The paper's step (kangcho/as_written.cpp, kangcho's impl=reference): builds the system at `state`,
// then dv(0) and `iterations` Jacobi sweeps into dv.
void paperStep(const StepProblem& problem, int iterations, LinearSystem& sys, Points& dv);

// One Jacobi sweep: dvNext_i = W_ii^-1 (b_i + h^2 sum_j J_ij dv_j); pinned stay prescribed.
void jacobiSweep(const Model& model, const LinearSystem& sys, const Points& dv, Points& dvNext);
// dv(0)_i = W_ii^-1 b_i (eq. 11, k = 0); pinned get their prescribed dv.
void jacobiStart(const LinearSystem& sys, Points& dv);

}  // namespace cloth
