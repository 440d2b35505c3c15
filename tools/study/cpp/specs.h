#pragma once
// Solvers and constraints from specs the study itself wrote: a spec that does not parse is a bug
// in the study, never a silent run of the default solver under the wrong label, so it stops the
// study (exit code 2) naming the spec.

#include <string>

#include "cloth/constraints.h"
#include "cloth/solvers/multigrid_settings.h"
#include "cloth/solver.h"

namespace study {

// The solver of `spec`; `tune`, if given, changes a multigrid's settled tuning.
cloth::SolverConfig configOf(const std::string& spec, void (*tune)(cloth::MultigridTuning&) = nullptr);

// The constraints of `spec` ("key=value,..."; "" for none).
cloth::Constraints constraintsOf(const std::string& spec);

}  // namespace study
