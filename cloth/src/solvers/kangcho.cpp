// kangcho: the paper's step. dv(0) = W_ii^-1 b_i, then `iterations` Jacobi sweeps (eq. 11); one
// sweep is eq. 14. The fast paths (stencil_kangcho.h for grids, fast_kangcho.h for any mesh)
// compute the same iterates without assembling the system; the reference path is the paper's
// step written equation by equation (paper_step.cpp). The tests compare all three.

#include "fast_kangcho.h"
#include "solver_table.h"
#include "solvers/step_common.h"
#include "stencil_kangcho.h"

namespace cloth {

namespace {

class KangChoSolver final : public ImplicitSolver {
public:
    explicit KangChoSolver(SolverConfig config) : ImplicitSolver(std::move(config)), s_(config_.get<KangChoSettings>()) {}

protected:
    bool computeDv(const Model& model, const Environment& env, const State& state, const StepInput& input,
                   StepResult& result) override {
        const auto t0 = Clock::now();
        result.iterations = s_.iterations;
        if (s_.impl == KangChoSettings::Impl::Reference) {
            paperStep(model, env, state, input, config_.compressionRule, s_.iterations, sys_, dv_);
            profile_.forcesMs = 0;
            profile_.solveMs = msSince(t0);
            return true;
        }
        if (model.id() != modelId_) {  // choose the layout once per model
            modelId_ = model.id();
            const bool stencil = s_.impl == KangChoSettings::Impl::Fast && !springFamilies(model).empty();
            if (s_.singlePrecision) fastFloat_.choose(stencil, s_.threads);
            else fastDouble_.choose(stencil, s_.threads);
        }
        if (s_.singlePrecision)
            fastFloat_.solve(model, env, state, input, config_.compressionRule, s_.iterations, dv_, &profile_.forcesMs);
        else
            fastDouble_.solve(model, env, state, input, config_.compressionRule, s_.iterations, dv_, &profile_.forcesMs);
        profile_.solveMs = msSince(t0) - profile_.forcesMs;
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
    KangChoSettings s_;
    std::uint64_t modelId_ = 0;
    Fast<float> fastFloat_;
    Fast<double> fastDouble_;
};

}  // namespace

SolverKind kangchoKind() {
    using S = KangChoSettings;
    using namespace keys;
    return {"kangcho",
            "the paper: dv(0) and Jacobi sweeps of the linearized backward Euler system (eqs. 11, 14)",
            [](SolverConfig& c) { c.settings = S{}; },
            with({shown(integer<S>("iterations", &S::iterations, 0, 100000, "Jacobi sweeps after dv(0); 1 = the paper's step")),
                  choice<S, S::Impl>("impl", &S::impl,
                                     {{"fast", S::Impl::Fast}, {"gather", S::Impl::Gather}, {"reference", S::Impl::Reference}},
                                     "fast: stencil layout on grids, else gather; reference: the paper's step as written"),
                  integer<S>("threads", &S::threads, 1, 64, "worker threads (bit-identical results for any count)"),
                  choice<S, bool>("precision", &S::singlePrecision, {{"double", false}, {"float", true}},
                                  "arithmetic of the step (the state stays double)")},
                 true),
            {},
            [](const SolverConfig& c) { return std::unique_ptr<Solver>(new KangChoSolver(c)); }};
}

}  // namespace cloth
