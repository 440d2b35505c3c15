// kangcho: the paper's step. dv(0) = W_ii^-1 b_i, then `iterations` Jacobi sweeps (eq. 11); one
// sweep is eq. 14. The fast paths (kangcho/stencil.h for grids, kangcho/gather.h for any mesh)
// compute the same iterates without assembling the system; the reference path is the paper's
// step written equation by equation (kangcho/paper_step.cpp). The tests compare all three.

#include "kangcho/gather.h"
#include "cloth/paper_step.h"
#include "cloth/solvers/kangcho_settings.h"
#include "cloth/solver_kind.h"
#include "solvers/step_common.h"
#include "kangcho/stencil.h"

namespace cloth {

namespace {

// The kind's settings; each field's key, with its doc, is in the kind's table below.

// The stencil layout when the model's springs form a few constant offsets, else the gather.
template <class T>
std::unique_ptr<KangChoLayout> layoutFor(ThreadPool& pool, std::vector<int> offsets) {
    if (!offsets.empty()) return std::make_unique<StencilKangCho<T>>(pool, std::move(offsets));
    return std::make_unique<GatherKangCho<T>>(pool);
}

class KangChoSolver final : public ImplicitSolver {
    bool computeDv(const StepProblem& problem, StepResult& result) override {
        const Model& model = problem.model;
        const KangchoSettings& s = settings<KangchoSettings>();
        const auto t0 = Clock::now();
        result.iterations = s.iterations;
        if (s.impl == KangchoSettings::Impl::Reference) {
            paperStep(problem, s.iterations, sys_, dv_);
            profile_.forcesMs = 0;
            profile_.solveMs = msSince(t0);
            return true;
        }
        if (model.id() != modelId_) {  // choose the layout once per model
            modelId_ = model.id();
            std::vector<int> offsets = s.impl == KangchoSettings::Impl::Fast ? springFamilies(model) : std::vector<int>();
            layout_ = s.singlePrecision ? layoutFor<float>(*pool_, std::move(offsets))
                                        : layoutFor<double>(*pool_, std::move(offsets));
        }
        layout_->solve(problem, s.iterations, dv_, &profile_.forcesMs);
        profile_.solveMs = msSince(t0) - profile_.forcesMs;
        return true;
    }

private:
    std::uint64_t modelId_ = 0;
    std::unique_ptr<KangChoLayout> layout_;  // stencil (grids) or gather, float or double
};

}  // namespace

FLAGSIM_SOLVER_KIND(kangcho) {
    using K = KangchoSettings;
    using key = SolverKeys;
    return {"kangcho", "the paper: dv(0) and Jacobi sweeps of the linearized backward Euler system (eqs. 11, 14)",
            defaultsTo<K>,
            withCommon({key::shown(key::integer("iterations", &K::iterations, 0, 100000,
                                                "Jacobi sweeps after dv(0); 1 = the paper's step")),
                        key::choice("impl", &K::impl,
                                    {{"fast", K::Impl::Fast}, {"gather", K::Impl::Gather}, {"reference", K::Impl::Reference}},
                                    "fast: stencil layout on grids, else gather; reference: the paper's step as written"),
                        threadsKey<K>(),
                        key::choice("precision", &K::singlePrecision, {{"double", false}, {"float", true}},
                                    "arithmetic of the step (the state stays double)")},
                       true),
            {},
            createSolver<KangChoSolver>};
}

}  // namespace cloth
