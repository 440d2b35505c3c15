#include "cloth/step_commit.h"

#include <utility>

#include "cloth/diagnostics.h"

namespace cloth {

StepResult commitStep(const Model& model, ConstraintSet& constraints, const StepInput& input, ThreadPool& pool,
                      State& state, State& scratch, StepResult result) {
    const Index n = static_cast<Index>(state.x.cols());
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= n) continue;
        scratch.x.col(p.particle) = p.x;
        scratch.v.col(p.particle) = p.v;
    }
    // The corrections run on a finite state only (what they leave is finite too); the check after
    // them decides whether the step is kept.
    if (constraints.any() && scratch.x.allFinite()) constraints.apply(model, input.pins, input.h, scratch, &pool);
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

}  // namespace cloth
