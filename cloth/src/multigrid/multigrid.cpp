#include "multigrid.h"

#include <chrono>
#include <cstdint>
#include <type_traits>

#include "cycle.h"
#include "fine_system.h"
#include "hierarchy.h"
#include "krylov.h"
#include "reductions.h"
#include "stopping.h"
#include "warm_start.h"

namespace cloth {

namespace {

HierarchyOptions hierarchyOptions(const MultigridTuning& t) {
    return {t.aggregation, t.coarsestParticles, t.stencilGalerkinMinRow};
}

CycleOptions cycleOptions(const MultigridTuning& t) { return {t.preSweeps, t.postSweeps, t.damping, t.kcycleLevels}; }

// Mixed precision: the same system in float (level 0 the double W rounded), whose cycles
// precondition the double CG. It shares the pool.
struct FloatCycles {
    FloatCycles(const MultigridTuning& t, ThreadPool& pool) : sums(pool), hierarchy(pool), cycle(cycleOptions(t), sums) {}
    Reductions sums;
    FineSystem<float> fine;
    Hierarchy<float> hierarchy;
    Cycle<float> cycle;
    std::uint64_t modelId = 0;
};

}  // namespace

MultigridTuning settledTuning(const MultigridSettings& settings) {
    MultigridTuning t;
    const bool adaptive = settings.cycles == 0;
    t.krylov = settings.cycles != 1 || settings.precision == MultigridSettings::Precision::Mixed;
    t.kcycleLevels = adaptive ? 1 : 0;
    t.startHistory = adaptive ? 2 : 0;
    return t;
}

template <class T>
struct Multigrid<T>::Impl {
    MultigridSettings settings;
    MultigridTuning tuning;
    std::shared_ptr<ThreadPool> pools;
    ThreadPool& pool;
    std::uint64_t modelId = 0;
    Reductions sums;
    FineSystem<T> fine;
    Hierarchy<T> hierarchy;
    Cycle<T> cycle;
    StoppingTest stop;
    WarmStart<T> warm;
    ConjugateGradients<T> cg;
    std::unique_ptr<FloatCycles> floats;
    std::vector<T> x, r;  // the solve's iterate and residual
    std::vector<T> px, py;  // product() in float: its operand and result

    Impl(const MultigridSettings& s, std::shared_ptr<ThreadPool> shared)
        : settings(s),
          tuning(s.tuning ? *s.tuning : settledTuning(s)),
          pools(shared ? std::move(shared) : std::make_shared<ThreadPool>(s.threads)),
          pool(*pools),
          sums(pool),
          hierarchy(pool),
          cycle(cycleOptions(tuning), sums),
          stop{s.tolerance, tuning.localTolerance},
          warm(tuning.startHistory),
          cg(sums) {
        if (std::is_same_v<T, double> && s.precision == MultigridSettings::Precision::Mixed)
            floats = std::make_unique<FloatCycles>(tuning, pool);
    }

    bool adaptive() const { return settings.cycles == 0; }
    int cap() const { return adaptive() ? settings.maxCycles : settings.cycles; }
    void prepareSystem(const StepProblem& problem);
    void refreshCoarse();
    void stationary(double bNorm, MultigridStats& stats);
    void conjugateGradients(double bNorm, MultigridStats& stats);
};

template <class T>
void Multigrid<T>::Impl::prepareSystem(const StepProblem& problem) {
    const Model& model = problem.model;
    if (modelId != model.id()) {
        modelId = model.id();
        warm.clear();
        hierarchy.prepare(model, fine, hierarchyOptions(tuning));
    }
    fine.build(problem, hierarchy.level(0), pool);
    if constexpr (std::is_same_v<T, double>) {
        if (!floats) return;
        if (floats->modelId != model.id()) {
            floats->modelId = model.id();
            floats->hierarchy.prepare(model, floats->fine, hierarchyOptions(tuning));
        }
        floats->fine.roundFrom(fine, hierarchy.level(0), floats->hierarchy.level(0), pool);
    }
}

// The coarse levels of the cycles: this hierarchy's, or with mixed precision the float one's.
template <class T>
void Multigrid<T>::Impl::refreshCoarse() {
    if (floats) floats->hierarchy.refresh(floats->fine, tuning.coarseEvery);
    else hierarchy.refresh(fine, tuning.coarseEvery);
}

// Cycles as a stationary iteration on W x = b (level 0's), from the warm start.
template <class T>
void Multigrid<T>::Impl::stationary(double bNorm, MultigridStats& stats) {
    Level<T>& L = hierarchy.level(0);
    double rel = warm.start(hierarchy, sums, bNorm, L.x, L.r);
    while (stats.cycles < cap() && (!adaptive() || !stop.converged(rel, L.r, L.x, L, sums))) {
        cycle.run(hierarchy, 0, true);
        ++stats.cycles;
        // The next cycle (if any) and the adaptive test need the residual; the last fixed one not.
        if (adaptive() || stats.cycles < cap()) hierarchy.residual(0, L.x, L.b, L.r);
        if (adaptive()) rel = sums.norm(L.r) / bNorm;
    }
    stats.residual = adaptive() ? rel : -1;
    x = L.x;
}

// Conjugate gradients preconditioned by one cycle per iteration, from the warm start.
template <class T>
void Multigrid<T>::Impl::conjugateGradients(double bNorm, MultigridStats& stats) {
    double rel = warm.start(hierarchy, sums, bNorm, x, r);
    KrylovSystem<T> system;
    system.apply = [this](const std::vector<T>& p, std::vector<T>& q) { hierarchy.product(0, p, nullptr, q); };
    system.precondition = [this](const std::vector<T>& res, std::vector<T>& z) {
        if (floats) floats->cycle.precondition(floats->hierarchy, res, z);
        else cycle.precondition(hierarchy, res, z);
    };
    system.converged = [this](double rel, const std::vector<T>& res, const std::vector<T>& at) {
        return stop.converged(rel, res, at, hierarchy.level(0), sums);
    };
    const KrylovControl control{cap(), adaptive(), !cycle.linear() || floats != nullptr, bNorm};
    stats.cycles = cg.solve(system, control, x, r, rel);
    stats.residual = adaptive() ? rel : -1;
}

template <class T>
Multigrid<T>::Multigrid(const MultigridSettings& settings, std::shared_ptr<ThreadPool> pool)
    : impl_(std::make_unique<Impl>(settings, std::move(pool))) {}

template <class T>
Multigrid<T>::~Multigrid() = default;

template <class T>
void Multigrid<T>::prepareSystem(const StepProblem& problem) {
    impl_->prepareSystem(problem);
}

template <class T>
bool Multigrid<T>::solve(const StepProblem& problem, Points& dv, MultigridStats& stats, double* forcesMs) {
    const auto t0 = std::chrono::steady_clock::now();
    Impl& m = *impl_;
    m.prepareSystem(problem);
    if (forcesMs) *forcesMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    m.refreshCoarse();
    const Level<T>& L = m.hierarchy.level(0);
    const int n = L.A.n;
    const double bNorm = m.sums.norm(L.b);
    stats = {};
    if (bNorm > 0 && m.tuning.krylov) m.conjugateGradients(bNorm, stats);
    else if (bNorm > 0) m.stationary(bNorm, stats);
    else m.x.assign(L.b.size(), T(0)), stats.residual = 0;
    dv.resize(3, n);
    double* out = dv.data();
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
            out[3 * i + a] = m.fine.pinned[i] ? double(m.fine.pinDv[3 * i + a]) : double(m.x[3 * std::size_t(i) + a]);
    m.warm.remember(m.x);
    return dv.allFinite();
}

template <class T>
int Multigrid<T>::levels() const {
    return impl_->hierarchy.size();
}

template <class T>
const BlockMatrix<T>& Multigrid<T>::matrix(int level) const {
    return impl_->hierarchy.level(level).A;
}

template <class T>
Eigen::MatrixXd Multigrid<T>::prolongation(int level) const {
    const Transfer& P = impl_->hierarchy.level(level).P;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(3 * P.fine, 3 * P.coarse);
    for (int i = 0; i < P.fine; ++i)
        for (int e = P.pStart[i]; e < P.pStart[i + 1]; ++e)
            for (int a = 0; a < 3; ++a) M(3 * i + a, 3 * P.pCol[e] + a) = P.pW[e];
    return M;
}

template <class T>
Eigen::VectorXd Multigrid<T>::vcycle(const Eigen::VectorXd& b) {
    return coarseSolve(0, b);
}

template <class T>
Eigen::VectorXd Multigrid<T>::coarseSolve(int level, const Eigen::VectorXd& b) {
    Impl& m = *impl_;
    m.hierarchy.invalidate();  // built now, for the system prepareSystem made, and recorded as such for solve()
    m.hierarchy.refresh(m.fine, m.tuning.coarseEvery);
    Level<T>& L = m.hierarchy.level(level);
    for (int q = 0; q < 3 * L.A.n; ++q) L.b[q] = T(b[q]) * L.active[q / 3], L.x[q] = T(0);
    L.r = L.b;
    m.cycle.coarseSolve(m.hierarchy, level);
    Eigen::VectorXd x(3 * L.A.n);
    for (int q = 0; q < 3 * L.A.n; ++q) x[q] = double(L.x[q]);
    return x;
}

template <class T>
void Multigrid<T>::rebuildCoarse() {
    impl_->hierarchy.invalidate();
    impl_->refreshCoarse();
}

template <class T>
void Multigrid<T>::product(const std::vector<double>& x, std::vector<double>& y) {
    Impl& m = *impl_;
    if constexpr (std::is_same_v<T, double>) {
        m.hierarchy.product(0, x, nullptr, y);
    } else {
        m.px.assign(x.begin(), x.end());
        m.hierarchy.product(0, m.px, nullptr, m.py);
        y.assign(m.py.begin(), m.py.end());
    }
    const Level<T>& L = m.hierarchy.level(0);
    for (std::size_t q = 0; q < y.size(); ++q) y[q] *= double(L.active[q / 3]);
}

template <class T>
void Multigrid<T>::precondition(const std::vector<double>& r, std::vector<double>& z) {
    Impl& m = *impl_;
    if (m.floats) m.floats->cycle.precondition(m.floats->hierarchy, r, z);
    else m.cycle.precondition(m.hierarchy, r, z);
    const Level<T>& L = m.hierarchy.level(0);
    for (std::size_t q = 0; q < z.size(); ++q) z[q] *= double(L.active[q / 3]);
}

template <class T>
std::string Multigrid<T>::describeHierarchy() const {
    return impl_->hierarchy.label() + (impl_->floats ? ", cycles in float" : "");
}

template class Multigrid<float>;
template class Multigrid<double>;

}  // namespace cloth
