#pragma once
// Solvers behind one small interface, chosen by kind with settings. Every kind has its file
// (src/solvers/KIND.cpp: the solver, its key table, its factory) and its public header
// (cloth/solvers/KIND_settings.h: its settings struct with its defaults), and registers in the solver
// registry (cloth/solver_kind.h). A config is made from a settings struct
// (`SolverConfig(MultigridSettings{.cycles = 2})`), or from text, "name[:key=value,...]", and a
// scene's JSON through the same keys (solver_config.h: the parsers, validation, describe(),
// makeSolver, the --help text, the README's solver table and the demo's panel, loops over the
// registry; `solverKindNames()` lists the kinds). Every implicit kind takes compression=
// (eq. 17). The corrections after a step (tethers, the stretch limit) are the cloth's
// constraints, not a solver's keys: Solver::setConstraints (constraints.h).
// A step never throws and never hands back a non-finite state: on failure the state is left as
// it was before the step and the status says why.

#include <any>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cloth/constraints.h"
#include "cloth/solvers/kangcho_settings.h"
#include "cloth/system.h"

namespace cloth {

struct SolverConfig {
    SolverConfig() : settings(KangchoSettings{}) {}  // the paper's step: kangcho at its defaults
    // A kind's settings struct (cloth/solvers/KIND_settings.h), which names its kind.
    template <class S>
        requires requires { S::kKind; }
    SolverConfig(S settings, bool compression = true)
        : name(S::kKind), compressionRule(compression), settings(std::move(settings)) {}
    std::string name = "kangcho";
    bool compressionRule = true;  // implicit kinds: eq. 17 in the Jacobian
    // The settings struct of the config's kind.
    std::any settings;
    // The settings of this config's kind (std::bad_any_cast for another kind's).
    template <class S>
    const S& get() const { return std::any_cast<const S&>(settings); }
    template <class S>
    S& get() { return std::any_cast<S&>(settings); }
};

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
    Solver() = default;  // solvers are made by createSolver (solver_kind.h), which sets config_ first
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

}  // namespace cloth
