#include "cloth/solver.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <charconv>
#include <chrono>
#include <cmath>
#include <sstream>

#include "cloth/diagnostics.h"
#include "cloth/strain_limit.h"
#include "fast_kangcho.h"
#include "multigrid.h"
#include "stencil_kangcho.h"

namespace cloth {

// ---------------------------------------------------------------------------------------------
// Configuration

namespace {
std::string shortNumber(Scalar v) {
    std::ostringstream s;
    s << v;
    return s.str();
}
}  // namespace

std::string SolverConfig::describe() const {
    std::ostringstream s;
    s << name;
    if (name == "kangcho")
        s << ":iterations=" << iterations << ",compression=" << (compressionRule ? "on" : "off")
          << (impl == Impl::Reference ? ",impl=reference" : impl == Impl::Gather ? ",impl=gather" : "") << (singlePrecision ? ",precision=float" : "")
          << (threads != 1 ? ",threads=" + std::to_string(threads) : std::string());
    else if (name == "exact" || name == "cg")
        s << ":"
          << (name == "cg" ? "" : method == Method::CG ? "method=cg," : method == Method::Multigrid ? "method=multigrid," : "method=cholesky,")
          << "tolerance=" << tolerance
          << (method != Method::Cholesky ? ",max_iterations=" + std::to_string(maxIterations) : std::string())
          << ",compression=" << (compressionRule ? "on" : "off");
    else if (name == "multigrid")
        s << ":cycles=" << cycles << (cycles == 0 ? ",tolerance=" + shortNumber(tolerance) + ",max_cycles=" + std::to_string(maxCycles) : std::string())
          << ",pre_sweeps=" << preSweeps << ",post_sweeps=" << postSweeps << ",damping=" << damping
          << (coarsening == Coarsening::Geometric ? ",coarsening=geometric" : coarsening == Coarsening::Aggregation ? ",coarsening=aggregation" : "")
          << (rediscretize ? ",coarse=rediscretize" : "") << (krylov ? "" : ",krylov=none")
          << ",compression=" << (compressionRule ? "on" : "off") << (singlePrecision ? ",precision=float" : "")
          << (threads != 1 ? ",threads=" + std::to_string(threads) : std::string());
    else if (name == "explicit")
        s << ":substeps=" << substeps;
    else if (name == "chebyshev")
        s << ":iterations=" << iterations << ",rho=" << rho;
    if (strainLimit > 0) s << ",strain_limit=" << strainLimit << ",strain_passes=" << strainLimitPasses;
    return s.str();
}

namespace {

bool parseInt(std::string_view text, int& out) {
    auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && p == text.data() + text.size();
}

bool parseDouble(std::string_view text, Scalar& out) {
    // std::from_chars for double is available in GCC 12.
    auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && p == text.data() + text.size() && std::isfinite(out);
}

bool parseSwitch(std::string_view text, bool& out) {
    if (text == "on" || text == "true" || text == "1") return out = true, true;
    if (text == "off" || text == "false" || text == "0") return out = false, true;
    return false;
}

}  // namespace

bool parseSolverConfig(std::string_view spec, SolverConfig& out, std::string* error) {
    auto failWith = [error](const std::string& msg) {
        if (error) *error = msg;
        return false;
    };
    SolverConfig c;
    const auto colon = spec.find(':');
    c.name = std::string(spec.substr(0, colon));
    if (c.name == "cg") c.method = SolverConfig::Method::CG;
    if (c.name == "multigrid") c.tolerance = 1e-3;
    if (c.name != "kangcho" && c.name != "exact" && c.name != "cg" && c.name != "explicit" && c.name != "chebyshev" &&
        c.name != "desbrun" && c.name != "multigrid")
        return failWith("unknown solver '" + c.name + "' (known: kangcho, exact, cg, explicit, chebyshev, desbrun, multigrid)");
    std::string_view rest = colon == std::string_view::npos ? "" : spec.substr(colon + 1);
    while (!rest.empty()) {
        const auto comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        rest = comma == std::string_view::npos ? "" : rest.substr(comma + 1);
        const auto eq = item.find('=');
        if (eq == std::string_view::npos)
            return failWith("solver parameter '" + std::string(item) + "' is not key=value");
        const std::string key(item.substr(0, eq));
        const std::string_view value = item.substr(eq + 1);
        bool ok = false;
        if (key == "iterations" && (c.name == "kangcho" || c.name == "chebyshev")) ok = parseInt(value, c.iterations);
        else if (key == "strain_limit") ok = parseDouble(value, c.strainLimit) && c.strainLimit >= 0 && c.strainLimit < 10;
        else if (key == "strain_passes") ok = parseInt(value, c.strainLimitPasses) && c.strainLimitPasses >= 1 && c.strainLimitPasses <= 1000;
        else if (key == "rho" && c.name == "chebyshev") ok = parseDouble(value, c.rho) && c.rho >= 0 && c.rho < 1;
        else if (key == "threads" && (c.name == "kangcho" || c.name == "multigrid")) ok = parseInt(value, c.threads);
        else if (key == "cycles" && c.name == "multigrid") ok = parseInt(value, c.cycles);
        else if (key == "max_cycles" && c.name == "multigrid") ok = parseInt(value, c.maxCycles);
        else if (key == "pre_sweeps" && c.name == "multigrid") ok = parseInt(value, c.preSweeps);
        else if (key == "post_sweeps" && c.name == "multigrid") ok = parseInt(value, c.postSweeps);
        else if (key == "damping" && c.name == "multigrid") ok = parseDouble(value, c.damping);
        else if (key == "coarsening" && c.name == "multigrid") {
            ok = value == "auto" || value == "geometric" || value == "aggregation";
            c.coarsening = value == "geometric"     ? SolverConfig::Coarsening::Geometric
                           : value == "aggregation" ? SolverConfig::Coarsening::Aggregation
                                                    : SolverConfig::Coarsening::Auto;
        } else if (key == "krylov" && c.name == "multigrid") {
            ok = value == "cg" || value == "none";
            c.krylov = value == "cg";
        } else if (key == "coarse" && c.name == "multigrid") {
            ok = value == "galerkin" || value == "rediscretize";
            c.rediscretize = value == "rediscretize";
        } else if (key == "precision" && (c.name == "kangcho" || c.name == "multigrid")) {
            ok = value == "float" || value == "double";
            c.singlePrecision = value == "float";
        } else if (key == "impl" && c.name == "kangcho") {
            ok = value == "fast" || value == "gather" || value == "reference";
            c.impl = value == "reference" ? SolverConfig::Impl::Reference
                     : value == "gather"  ? SolverConfig::Impl::Gather
                                          : SolverConfig::Impl::Fast;
        }
        else if (key == "compression" && c.name != "explicit") ok = parseSwitch(value, c.compressionRule);
        else if (key == "tolerance" && (c.name == "exact" || c.name == "cg" || c.name == "multigrid"))
            ok = parseDouble(value, c.tolerance);
        else if (key == "max_iterations" && (c.name == "exact" || c.name == "cg")) ok = parseInt(value, c.maxIterations);
        else if (key == "method" && c.name == "exact") {
            ok = value == "cg" || value == "cholesky" || value == "multigrid";
            c.method = value == "cg"          ? SolverConfig::Method::CG
                       : value == "multigrid" ? SolverConfig::Method::Multigrid
                                              : SolverConfig::Method::Cholesky;
        } else if (key == "substeps" && c.name == "explicit") ok = parseInt(value, c.substeps);
        else return failWith("solver '" + c.name + "' has no parameter '" + key + "'");
        if (!ok)
            return failWith("solver '" + c.name + "' parameter " + key + " has a bad value '" +
                            std::string(value) + "'");
    }
    const std::string problem = validate(c);
    if (!problem.empty()) return failWith(problem);
    out = c;
    return true;
}

std::string validate(const SolverConfig& c) {
    if (c.name != "kangcho" && c.name != "exact" && c.name != "cg" && c.name != "explicit" && c.name != "chebyshev" &&
        c.name != "desbrun" && c.name != "multigrid")
        return "unknown solver '" + c.name + "'";
    if (c.cycles < 0 || c.cycles > 1000) return "cycles = " + std::to_string(c.cycles) + " must be in [0, 1000]";
    if (c.maxCycles < 1 || c.maxCycles > 1000)
        return "max_cycles = " + std::to_string(c.maxCycles) + " must be in [1, 1000]";
    if (c.preSweeps < 0 || c.preSweeps > 100 || c.postSweeps < 0 || c.postSweeps > 100)
        return "pre_sweeps and post_sweeps must be in [0, 100]";
    if (c.preSweeps + c.postSweeps == 0) return "pre_sweeps + post_sweeps must be at least 1";
    if (!(c.damping > 0 && c.damping <= 1.5)) return "damping = " + shortNumber(c.damping) + " must be in (0, 1.5]";
    if (c.name == "multigrid" && c.singlePrecision && c.tolerance < 1e-6)
        return "tolerance = " + shortNumber(c.tolerance) + " is below what precision=float can reach (>= 1e-6)";
    if (c.iterations < 0 || c.iterations > 100000)
        return "iterations = " + std::to_string(c.iterations) + " must be in [0, 100000]";
    if (!(c.tolerance > 0 && c.tolerance < 1))
        return "tolerance = " + std::to_string(c.tolerance) + " must be in (0, 1)";
    if (c.threads < 1 || c.threads > 64) return "threads = " + std::to_string(c.threads) + " must be in [1, 64]";
    if (c.maxIterations < 1) return "max_iterations = " + std::to_string(c.maxIterations) + " must be >= 1";
    if (c.substeps < 1 || c.substeps > 100000)
        return "substeps = " + std::to_string(c.substeps) + " must be in [1, 100000]";
    return {};
}

const char* toString(StepStatus status) {
    switch (status) {
        case StepStatus::Ok: return "ok";
        case StepStatus::NonFinite: return "non-finite state";
        case StepStatus::SolverFailed: return "solver failed";
    }
    return "?";
}

// ---------------------------------------------------------------------------------------------
// Shared pieces of the implicit step

void jacobiStart(const LinearSystem& sys, Points& dv) {
    const Index n = static_cast<Index>(sys.diag.size());
    dv.resize(3, n);
    for (Index i = 0; i < n; ++i) dv.col(i) = sys.diagInv[i] * sys.rhs.col(i);
}

void jacobiSweep(const Model& model, const LinearSystem& sys, const Points& dv, Points& dvNext) {
    applyOffDiagonal(model, sys, dv, dvNext);  // dvNext_i = h^2 sum_j J_ij dv_j
    for (Index i = 0; i < model.particleCount(); ++i)
        dvNext.col(i) = sys.diagInv[i] * (sys.rhs.col(i) + dvNext.col(i));
}

bool solveExact(const Model& model, const LinearSystem& sys, Points& dv, Scalar* residual) {
    const Eigen::SparseMatrix<Scalar> W = assembleMatrix(model, sys);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<Scalar>> chol(W);
    if (chol.info() != Eigen::Success) return false;
    const Eigen::Map<const Eigen::VectorXd> b(sys.rhs.data(), sys.rhs.size());
    Eigen::VectorXd x = chol.solve(b);
    // Iterative refinement: a couple of residual corrections bring the relative residual to
    // rounding level even for ill-conditioned (stiff, small h) systems.
    const Scalar bNorm = std::max(b.norm(), Scalar(1e-300));
    Scalar rel = (W * x - b).norm() / bNorm;
    for (int k = 0; k < 3 && rel > 1e-12; ++k) {
        x += chol.solve(b - W * x);
        rel = (W * x - b).norm() / bNorm;
    }
    if (residual) *residual = rel;
    dv = Eigen::Map<const Points>(x.data(), 3, model.particleCount());
    return x.allFinite();
}

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Writes the step's outcome into `state`, or leaves it untouched when anything is non-finite.
// Pinned particles land exactly on their targets with their target velocity; then the optional
// anti-stretch pass (pinned particles stay put).
StepResult commit(const Model& model, const SolverConfig& config, const StepInput& input, State& state,
                  State& scratch, StepResult result) {
    const Index n = static_cast<Index>(state.x.cols());
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= n) continue;
        scratch.x.col(p.particle) = p.x;
        scratch.v.col(p.particle) = p.v;
    }
    if (config.strainLimit > 0 && scratch.x.allFinite()) {
        static thread_local std::vector<std::uint8_t> pinned;
        pinned.assign(n, 0);
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < n) pinned[p.particle] = 1;
        limitStretch(model, pinned, config.strainLimit, config.strainLimitPasses, input.h, scratch);
    }
    const Index bad = firstNonFinite(scratch);
    if (bad >= 0) {
        result.status = StepStatus::NonFinite;
        result.badParticle = bad;
        return result;
    }
    std::swap(state.x, scratch.x);
    std::swap(state.v, scratch.v);
    return result;
}

// Backward Euler step shape shared by every implicit solver: build the system, solve for dv,
// then v += dv, x += h v. Subclasses supply the solve.
class ImplicitSolver : public Solver {
public:
    using Solver::Solver;
    StepResult step(const Model& model, const Environment& env, State& state,
                    const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        StepResult result;
        if (input.damping && Index(input.damping->size()) != model.particleCount()) return {StepStatus::SolverFailed, -1};
        if (!computeDv(model, env, state, input, result)) result.status = StepStatus::SolverFailed;
        if (result.status != StepStatus::Ok) return result;

        const auto t0 = Clock::now();
        const Scalar h = input.h;
        scratch_.v = state.v + dv_;
        scratch_.x = state.x + h * scratch_.v;
        result = commit(model, config_, input, state, scratch_, result);
        profile_.integrateMs = msSince(t0);
        return result;
    }

protected:
    // Fills dv_ and profile_.forcesMs / solveMs. By default: the assembled system, then solve().
    virtual bool computeDv(const Model& model, const Environment& env, const State& state,
                           const StepInput& input, StepResult& result) {
        auto t0 = Clock::now();
        buildSystem(model, env, state, input, config_.compressionRule, sys_);
        profile_.forcesMs = msSince(t0);
        t0 = Clock::now();
        const bool ok = solve(model, result);
        profile_.solveMs = msSince(t0);
        return ok;
    }
    virtual bool solve(const Model& model, StepResult& result) = 0;
    LinearSystem sys_;
    State scratch_;
};

// Kang & Cho: dv(0) = W_ii^-1 b_i, then `iterations` Jacobi sweeps (eq. 11); one sweep is eq. 14.
// The fast paths (stencil_kangcho.h for grids, fast_kangcho.h for any mesh) compute the same
// iterates without assembling the system; the reference path assembles it and sweeps over 3x3
// blocks (the tests compare all three).
class KangChoSolver final : public ImplicitSolver {
public:
    using ImplicitSolver::ImplicitSolver;

protected:
    bool computeDv(const Model& model, const Environment& env, const State& state, const StepInput& input,
                   StepResult& result) override {
        using Impl = SolverConfig::Impl;
        if (config_.impl == Impl::Reference) return ImplicitSolver::computeDv(model, env, state, input, result);
        if (model.id() != modelId_) {  // choose the layout once per model
            modelId_ = model.id();
            const bool stencil = config_.impl == Impl::Fast && !springFamilies(model).empty();
            if (config_.singlePrecision) fastFloat_.choose(stencil, config_.threads);
            else fastDouble_.choose(stencil, config_.threads);
        }
        const auto t0 = Clock::now();
        if (config_.singlePrecision)
            fastFloat_.solve(model, env, state, input, config_.compressionRule, config_.iterations, dv_,
                             &profile_.forcesMs);
        else
            fastDouble_.solve(model, env, state, input, config_.compressionRule, config_.iterations, dv_,
                              &profile_.forcesMs);
        profile_.solveMs = msSince(t0) - profile_.forcesMs;
        result.iterations = config_.iterations;
        return true;
    }
    bool solve(const Model& model, StepResult& result) override {
        jacobiStart(sys_, dv_);
        for (int k = 0; k < config_.iterations; ++k) {
            jacobiSweep(model, sys_, dv_, next_);
            std::swap(dv_, next_);
        }
        result.iterations = config_.iterations;
        return true;
    }

private:
    // One of the two fast layouts in precision T.
    template <class T>
    struct Fast {
        std::unique_ptr<StencilKangCho<T>> stencil;
        std::unique_ptr<FastKangCho<T>> gather;
        void choose(bool useStencil, int threads) {
            stencil.reset();
            gather.reset();
            if (useStencil) stencil = std::make_unique<StencilKangCho<T>>(threads);
            else gather = std::make_unique<FastKangCho<T>>(threads);
        }
        template <class... Args>
        void solve(Args&&... args) {
            if (stencil) stencil->solve(std::forward<Args>(args)...);
            else gather->solve(std::forward<Args>(args)...);
        }
    };
    std::uint64_t modelId_ = 0;
    Points next_;
    Fast<float> fastFloat_;
    Fast<double> fastDouble_;
};

// The reference: the same system solved exactly (sparse Cholesky), or by conjugate gradients
// to a tolerance (block-free diagonal preconditioner).
class ExactSolver final : public ImplicitSolver {
public:
    using ImplicitSolver::ImplicitSolver;

protected:
    bool computeDv(const Model& model, const Environment& env, const State& state, const StepInput& input,
                   StepResult& result) override {
        if (config_.method != SolverConfig::Method::Multigrid)
            return ImplicitSolver::computeDv(model, env, state, input, result);
        // V-cycles until the relative residual is under the tolerance: an exact solve at O(n) per
        // cycle. Not reaching it within max_iterations cycles is a failure, not an approximation.
        if (!multigrid_) {
            MultigridSettings s;
            s.tolerance = config_.tolerance;
            s.maxCycles = std::min(config_.maxIterations, 1000);
            s.conjugateGradients = true;
            multigrid_ = std::make_unique<Multigrid<double>>(s, 1);
        }
        MultigridStats stats;
        const auto t0 = Clock::now();
        const bool ok = multigrid_->solve(model, env, state, input, config_.compressionRule, dv_, stats, &profile_.forcesMs);
        profile_.solveMs = msSince(t0) - profile_.forcesMs;
        result.iterations = stats.cycles;
        result.residual = stats.residual;
        return ok && stats.residual <= config_.tolerance;
    }
    bool solve(const Model& model, StepResult& result) override {
        if (config_.method == SolverConfig::Method::Cholesky) {
            result.iterations = 1;
            return solveExact(model, sys_, dv_, &result.residual);
        }
        const Eigen::SparseMatrix<Scalar> W = assembleMatrix(model, sys_);
        Eigen::ConjugateGradient<Eigen::SparseMatrix<Scalar>, Eigen::Lower | Eigen::Upper> cg;
        cg.setTolerance(config_.tolerance);
        cg.setMaxIterations(config_.maxIterations);
        cg.compute(W);
        const Eigen::Map<const Eigen::VectorXd> b(sys_.rhs.data(), sys_.rhs.size());
        // Warm start from the Jacobi guess dv(0): cheap and always at least as good as zero.
        jacobiStart(sys_, dv_);
        Eigen::VectorXd x0 = Eigen::Map<const Eigen::VectorXd>(dv_.data(), dv_.size());
        Eigen::VectorXd x = cg.solveWithGuess(b, x0);
        result.iterations = static_cast<int>(cg.iterations());
        result.residual = cg.error();
        dv_ = Eigen::Map<const Points>(x.data(), 3, model.particleCount());
        return x.allFinite();
    }

private:
    std::unique_ptr<Multigrid<double>> multigrid_;
};

// Multigrid V-cycles on the system of the paper's step (multigrid.h): the paper's Jacobi sweep,
// damped, as the smoother, Galerkin coarse operators, a direct solve on the coarsest level.
// A fixed number of cycles, or (cycles=0) until the relative residual is under the tolerance,
// with a cap; the count used is in the step's result.
class MultigridSolver final : public ImplicitSolver {
public:
    explicit MultigridSolver(SolverConfig config) : ImplicitSolver(std::move(config)) {
        MultigridSettings s;
        s.cycles = config_.cycles;
        s.tolerance = config_.tolerance;
        s.maxCycles = config_.maxCycles;
        s.preSweeps = config_.preSweeps;
        s.postSweeps = config_.postSweeps;
        s.damping = config_.damping;
        s.coarsening = config_.coarsening == SolverConfig::Coarsening::Geometric     ? MultigridSettings::Coarsening::Geometric
                       : config_.coarsening == SolverConfig::Coarsening::Aggregation ? MultigridSettings::Coarsening::Aggregation
                                                                                     : MultigridSettings::Coarsening::Auto;
        s.conjugateGradients = config_.krylov;
        s.coarseOperator = config_.rediscretize ? MultigridSettings::CoarseOperator::Rediscretized
                                                : MultigridSettings::CoarseOperator::Galerkin;
        if (config_.singlePrecision) float_ = std::make_unique<Multigrid<float>>(s, config_.threads);
        else double_ = std::make_unique<Multigrid<double>>(s, config_.threads);
    }
    std::string details() const override {
        return "levels: " + (float_ ? float_->describeHierarchy() : double_->describeHierarchy());
    }

protected:
    bool computeDv(const Model& model, const Environment& env, const State& state, const StepInput& input,
                   StepResult& result) override {
        MultigridStats stats;
        const auto t0 = Clock::now();
        const bool ok = float_ ? float_->solve(model, env, state, input, config_.compressionRule, dv_, stats, &profile_.forcesMs)
                               : double_->solve(model, env, state, input, config_.compressionRule, dv_, stats, &profile_.forcesMs);
        profile_.solveMs = msSince(t0) - profile_.forcesMs;
        result.iterations = stats.cycles;
        result.residual = stats.residual;
        return ok;
    }
    bool solve(const Model&, StepResult&) override { return false; }  // computeDv does it all

private:
    std::unique_ptr<Multigrid<float>> float_;
    std::unique_ptr<Multigrid<double>> double_;
};

// Jacobi with Chebyshev semi-iterative acceleration (H. Wang, "A Chebyshev Semi-Iterative
// Approach for Accelerating Projective and Position-based Dynamics", SIGGRAPH Asia 2015):
//   x(k+1) = w(k+1) (J(x(k)) - x(k-1)) + x(k-1),  w1 = 1, w2 = 2 / (2 - rho^2),
//   w(k+1) = 4 / (4 - rho^2 w(k)),
// where J is one Jacobi sweep and rho the spectral radius of the Jacobi iteration. Each iteration
// costs one sweep, like the paper's; rho is estimated from the system unless given: for springs
// along a line, h^2 sum_j k_ij / (m_i + h^2 sum_j k_ij) is the scalar Jacobi radius bound.
class ChebyshevSolver final : public ImplicitSolver {
public:
    using ImplicitSolver::ImplicitSolver;

protected:
    bool solve(const Model& model, StepResult& result) override {
        Scalar rho = config_.rho;
        if (rho <= 0) {
            const Scalar h2 = sys_.h * sys_.h;
            std::vector<Scalar> ksum(model.particleCount(), 0);
            for (const Spring& s : model.springs()) ksum[s.i] += s.k, ksum[s.j] += s.k;
            for (Index i = 0; i < model.particleCount(); ++i)
                if (!sys_.pinned[i]) rho = std::max(rho, h2 * ksum[i] / (model.masses()[i] + h2 * ksum[i]));
            rho = std::min(rho, Scalar(0.9999));
        }
        jacobiStart(sys_, dv_);
        prev_ = dv_;
        Scalar omega = 1;
        for (int k = 1; k <= config_.iterations; ++k) {
            jacobiSweep(model, sys_, dv_, next_);
            omega = k == 1 ? 1 : (k == 2 ? 2 / (2 - rho * rho) : 4 / (4 - rho * rho * omega));
            next_ = omega * (next_ - prev_) + prev_;  // pinned rows: prescribed in both, unchanged
            std::swap(prev_, dv_);
            std::swap(dv_, next_);
        }
        result.iterations = config_.iterations;
        return true;
    }

private:
    Points prev_, next_;
};

// Desbrun, Schroder & Barr 1999 ("Interactive animation of structured deformable objects"), the
// paper's ref. [5]: the Jacobian is replaced by its constant, isotropic linear part, J_ij ~ k I
// (a Laplacian of spring stiffnesses), so the implicit matrix A = M + h^2 k L (x) I3 never changes
// and is factored once ("precomputed filter"); each step solves
//   A dv = h f(x) - h^2 k L v        (f with the full nonlinear springs)
// three times (x, y, z) with that factorization. Pinned particles are eliminated as everywhere
// here. Desbrun et al.'s post-step correction of the angular momentum the filter disturbs is not
// applied (documented in docs/study.md).
class DesbrunSolver final : public Solver {
public:
    using Solver::Solver;
    StepResult step(const Model& model, const Environment& env, State& state, const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        const Index n = model.particleCount();
        const Scalar h = input.h, h2 = h * h;
        auto t0 = Clock::now();
        std::vector<std::uint8_t> pinned(n, 0);
        Points pinDv = Points::Zero(3, n);
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < n) {
                pinned[p.particle] = 1;
                pinDv.col(p.particle) = (p.x - state.x.col(p.particle)) / h - state.v.col(p.particle);
            }
        if (model.id() != modelId_ || h != h_ || pinned != pinned_) factor(model, env, h, pinned);
        computeForces(model, env, state, input.externalForce, force_);
        // b = h f - h^2 k L v, with pinned columns moved to the right-hand side.
        Eigen::MatrixXd b = (h * force_).transpose();  // n x 3
        for (const Spring& s : model.springs()) {
            const Vec3 lv = s.k * (state.v.col(s.j) - state.v.col(s.i));  // (k L v) on i is -k (v_j - v_i)
            b.row(s.i) += h2 * lv.transpose();
            b.row(s.j) -= h2 * lv.transpose();
            if (pinned[s.j]) b.row(s.i) += h2 * s.k * pinDv.col(s.j).transpose();
            if (pinned[s.i]) b.row(s.j) += h2 * s.k * pinDv.col(s.i).transpose();
        }
        for (Index i = 0; i < n; ++i)
            if (pinned[i]) b.row(i) = pinDv.col(i).transpose();
        profile_.forcesMs = msSince(t0);
        t0 = Clock::now();
        const Eigen::MatrixXd dv = chol_.solve(b);
        dv_ = dv.transpose();
        profile_.solveMs = msSince(t0);
        if (chol_.info() != Eigen::Success || !dv_.allFinite()) return {StepStatus::SolverFailed, -1};
        t0 = Clock::now();
        scratch_.v = state.v + dv_;
        scratch_.x = state.x + h * scratch_.v;
        StepResult r = commit(model, config_, input, state, scratch_, StepResult{});
        profile_.integrateMs = msSince(t0);
        return r;
    }

private:
    void factor(const Model& model, const Environment& env, Scalar h, const std::vector<std::uint8_t>& pinned) {
        const Index n = model.particleCount();
        std::vector<Eigen::Triplet<Scalar>> t;
        for (Index i = 0; i < n; ++i)
            t.emplace_back(i, i, pinned[i] ? 1.0 : model.masses()[i] * (1 + h * env.drag));
        for (const Spring& s : model.springs()) {
            const Scalar w = h * h * s.k;
            if (!pinned[s.i]) t.emplace_back(s.i, s.i, w);
            if (!pinned[s.j]) t.emplace_back(s.j, s.j, w);
            if (!pinned[s.i] && !pinned[s.j]) {
                t.emplace_back(s.i, s.j, -w);
                t.emplace_back(s.j, s.i, -w);
            }
        }
        Eigen::SparseMatrix<Scalar> A(n, n);
        A.setFromTriplets(t.begin(), t.end());
        chol_.compute(A);
        modelId_ = model.id();
        h_ = h;
        pinned_ = pinned;
    }
    Eigen::SimplicialLLT<Eigen::SparseMatrix<Scalar>> chol_;
    std::uint64_t modelId_ = 0;
    Scalar h_ = 0;
    std::vector<std::uint8_t> pinned_;
    Points force_;
    State scratch_;
};

// Symplectic Euler with substeps: v += hs f / m, x += hs v. Pinned particles move straight to
// their targets.
class ExplicitSolver final : public Solver {
public:
    using Solver::Solver;
    StepResult step(const Model& model, const Environment& env, State& state,
                    const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        const Index n = model.particleCount();
        const int substeps = config_.substeps;
        const Scalar hs = input.h / substeps;
        const auto& mass = model.masses();
        std::vector<std::uint8_t> pinned(n, 0);
        Points pinVelocity = Points::Zero(3, n);
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < n) {
                pinned[p.particle] = 1;
                pinVelocity.col(p.particle) = (p.x - state.x.col(p.particle)) / input.h;
            }
        profile_ = {};
        scratch_.x = state.x;
        scratch_.v = state.v;
        for (int k = 0; k < substeps; ++k) {
            auto t0 = Clock::now();
            computeForces(model, env, scratch_, input.externalForce, force_);
            profile_.forcesMs += msSince(t0);
            t0 = Clock::now();
            for (Index i = 0; i < n; ++i) {
                if (pinned[i]) scratch_.v.col(i) = pinVelocity.col(i);
                else scratch_.v.col(i) += hs / mass[i] * force_.col(i);
                scratch_.x.col(i) += hs * scratch_.v.col(i);
            }
            profile_.solveMs += msSince(t0);
        }
        auto t0 = Clock::now();
        dv_ = scratch_.v - state.v;
        StepResult result = commit(model, config_, input, state, scratch_, StepResult{});
        result.iterations = substeps;
        profile_.integrateMs = msSince(t0);
        return result;
    }

private:
    State scratch_;
    Points force_;
};

}  // namespace

std::unique_ptr<Solver> makeSolver(const SolverConfig& config, std::string* error) {
    const std::string problem = validate(config);
    if (!problem.empty()) {
        if (error) *error = problem;
        return nullptr;
    }
    if (config.name == "kangcho") return std::unique_ptr<Solver>(new KangChoSolver(config));
    if (config.name == "chebyshev") return std::unique_ptr<Solver>(new ChebyshevSolver(config));
    if (config.name == "desbrun") return std::unique_ptr<Solver>(new DesbrunSolver(config));
    if (config.name == "multigrid") return std::unique_ptr<Solver>(new MultigridSolver(config));
    if (config.name == "exact" || config.name == "cg") {
        SolverConfig c = config;
        if (c.name == "cg") c.method = SolverConfig::Method::CG;
        return std::unique_ptr<Solver>(new ExactSolver(c));
    }
    return std::unique_ptr<Solver>(new ExplicitSolver(config));
}

}  // namespace cloth
