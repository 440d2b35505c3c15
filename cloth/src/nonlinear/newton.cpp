#include "newton.h"

#include "cloth/forces.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cloth {

namespace {

Scalar merit(const Model& model, const Points& residual) {  // |R|^2_{M^-1}
    Scalar sum = 0;
    for (Index i = 0; i < model.particleCount(); ++i) sum += residual.col(i).squaredNorm() / model.masses()[i];
    return sum;
}

}  // namespace

NewtonSolve::NewtonSolve(std::shared_ptr<ThreadPool> pool)
    : pool_(std::move(pool)), sums_(*pool_), multigrid_(MultigridSettings{}, pool_), gmres_(sums_) {}

NewtonSolve::~NewtonSolve() = default;

// The Jacobians at `at`: the air's (when coupled), level 0 of the preconditioner's hierarchy and,
// for an exact Newton matrix, what eq. 17 leaves out of it: J - J_17 = k (1 - l0/L) (I - u u^T)
// on every compressed spring.
void NewtonSolve::linearize(const StepEquations& eq, const State& at, bool exact) {
    compressed_.clear();
    if (exact && eq.compressionRule) compressed_.build(eq.model, at.x, *pool_);
    StepInput in;
    in.h = eq.k;
    in.pins = eq.input.pins;
    if (eq.input.air) {
        air_.compute(eq.model, at, *eq.input.air, pool_.get());
        air_.velocityDiagonal(eq.model, airDiagonal_, pool_.get());
        airDamping(airDiagonal_, airDamping_, pool_.get());
        in.damping = &airDamping_;
    } else {
        in.damping = eq.input.damping;  // the caller's frozen air's drag, implicit in velocity
    }
    multigrid_.prepareSystem({eq.model, eq.env, at, in, eq.compressionRule});
}

// y = A x, A = W + k (df/dv + k df/dx of the air) - k C_air - k^2 (J - J_17) (W: the hierarchy's
// level 0, which holds eq. 17's springs and the air's symmetric positive diagonal C_air). Each
// pass is split among the pool's threads; a row adds its terms in a fixed order.
void NewtonSolve::product(const StepEquations& eq, const std::vector<double>& x, std::vector<double>& y) {
    const Scalar k = eq.k;
    const bool air = eq.input.air != nullptr;
    multigrid_.product(x, y);
    compressed_.subtract(x.data(), k * k, pinned_, y.data(), *pool_);
    if (!air) return;
    air_.triangleParts(eq.model, x.data(), k * k, k, pool_.get());
    parts_.resize(x.size());
    pool_->run(int(eq.model.particleCount()), [&](int begin, int end) {
        std::fill(parts_.begin() + 3 * begin, parts_.begin() + 3 * end, 0.0);
        air_.addParts(eq.model, begin, end, parts_.data());
        for (Index i = begin; i < end; ++i) {
            if (pinned_[i]) continue;
            const Vec3 c = airDamping_[i] * Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
            for (int a = 0; a < 3; ++a) y[3 * i + a] -= k * c[a] + parts_[3 * i + a];
        }
    });
}

// delta from A delta = rhs (product() above), by flexible GMRES preconditioned by W's cycles.
int NewtonSolve::solveLinear(const StepEquations& eq, const NewtonControl& control, const Points& rhs, Points& delta) {
    KrylovSystem<double> system;
    system.apply = [&](const std::vector<double>& x, std::vector<double>& y) { product(eq, x, y); };
    system.precondition = [&](const std::vector<double>& r, std::vector<double>& z) { multigrid_.precondition(r, z); };
    b_.assign(rhs.data(), rhs.data() + rhs.size());
    x_.assign(b_.size(), 0.0);
    double rel = 0;
    const int iterations = gmres_.solve(system, {30, control.maxLinearIterations, control.linearTolerance}, b_, x_, rel);
    delta = Eigen::Map<const Points>(x_.data(), 3, eq.model.particleCount());
    return iterations;
}

// The forces and the residual at `at`; returns max |R_i| / m_i.
Scalar NewtonSolve::evaluate(const StepEquations& eq, const State& at) {
    stepForces(eq, at, force_, pool_.get(), &airWorkspace_);
    return stepResidual(eq, at, force_, pinned_, residual_);
}

// iterate += alpha delta for the first alpha in 1, 1/2, ..., 1/64 that lowers |R|_{M^-1} enough
// (Armijo), else the lowest of them if it is lower than now, else no step: false. On a step, the
// forces and the residual at the new iterate are in force_ and residual_, and stats.residual is
// their max |R_i| / m_i.
bool NewtonSolve::lineSearch(const StepEquations& eq, const Points& delta, State& iterate, Scalar& current,
                             NewtonStats& stats) {
    State trial = iterate;
    Scalar best = current, bestAlpha = 0, alpha = 1, worst = 0;
    for (;; alpha /= 2) {
        trial.v = iterate.v + alpha * delta;
        stagePositions(eq, trial);
        stepForces(eq, trial, trialForce_, pool_.get(), &airWorkspace_);
        worst = stepResidual(eq, trial, trialForce_, pinned_, trialResidual_);
        const Scalar m = merit(eq.model, trialResidual_);
        if (m < best) best = m, bestAlpha = alpha;
        if (m < current * (1 - Scalar(1e-4) * alpha) || alpha <= Scalar(1) / 64) break;
    }
    if (bestAlpha == 0) return false;
    iterate.v += bestAlpha * delta;
    stagePositions(eq, iterate);
    current = best;
    if (bestAlpha == alpha) {  // the last trial is the new iterate: its forces are already known
        std::swap(force_, trialForce_);
        std::swap(residual_, trialResidual_);
        stats.residual = worst;
    } else {
        stats.residual = evaluate(eq, iterate);
    }
    return true;
}

bool NewtonSolve::solve(const StepEquations& eq, const NewtonControl& control, State& iterate, NewtonStats& stats) {
    const Model& model = eq.model;
    const Index n = model.particleCount();
    stats = {};
    pinned_.assign(n, 0);
    for (const Pin& p : eq.input.pins)
        if (p.particle >= 0 && p.particle < n) pinned_[p.particle] = 1;
    // Iteration 1, linearized at the start (iterate.x = x_n): with r1 = x_n - x(v),
    // A dv = -R - k K r1 (K = df/dx: springs and air).
    linearize(eq, iterate, false);
    multigrid_.rebuildCoarse();  // the coarse levels stay for the later iterations of the step
    evaluate(eq, iterate);
    State staged = iterate;
    stagePositions(eq, staged);
    const Points r1 = iterate.x - staged.x;
    Points rhs;
    springStiffnessTimes(model, iterate.x, eq.compressionRule, r1, rhs);
    if (eq.input.air) air_.apply(model, r1.data(), 1, 0, rhs.data());
    rhs = -residual_ - eq.k * rhs;
    for (Index i = 0; i < n; ++i)
        if (pinned_[i]) rhs.col(i).setZero();
    Points delta;
    stats.linearIterations += solveLinear(eq, control, rhs, delta);
    iterate.v += delta;
    stagePositions(eq, iterate);
    stats.iterations = 1;
    stats.residual = evaluate(eq, iterate);
    stats.correction = delta.cwiseAbs().maxCoeff();
    Scalar current = merit(model, residual_);
    while (std::isfinite(current) && stats.correction > control.tolerance && stats.iterations < control.maxIterations) {
        linearize(eq, iterate, true);
        stats.linearIterations += solveLinear(eq, control, -residual_, delta);
        ++stats.iterations;
        const Points before = iterate.v;
        bool moved = lineSearch(eq, delta, iterate, current, stats);
        if (!moved && !compressed_.empty()) {  // the exact matrix's direction failed: eq. 17's
            compressed_.clear();
            stats.linearIterations += solveLinear(eq, control, -residual_, delta);
            moved = lineSearch(eq, delta, iterate, current, stats);
        }
        if (!moved) break;
        stats.correction = (iterate.v - before).cwiseAbs().maxCoeff();
    }
    return std::isfinite(current) && iterate.x.allFinite() && iterate.v.allFinite();
}

}  // namespace cloth
