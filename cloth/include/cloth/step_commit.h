#pragma once
// The end of every solver's step (src/solvers/step_commit.cpp): what a solver kind, the
// library's or a program's own (solver_kind.h), calls once it has the step's outcome.

#include "cloth/constraints.h"
#include "cloth/solver.h"
#include "cloth/thread_pool.h"

namespace cloth {

// Writes the step's outcome `scratch` into `state`, or leaves `state` untouched when anything is
// non-finite. Pinned particles land exactly on their targets with their target velocity; then
// the cloth's constraints: tethers, then the stretch limit (pinned particles stay put).
StepResult commitStep(const Model& model, ConstraintSet& constraints, const StepInput& input, ThreadPool& pool,
                      State& state, State& scratch, StepResult result);

}  // namespace cloth
