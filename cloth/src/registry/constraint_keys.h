#pragma once
// The cloth's constraints' keys (constraints.h: tether, stretch_limit, stretch_passes) as a key
// table; --help and the README's table print them after the solvers' (solver_registry.h).

#include <vector>

#include "cloth/constraints.h"
#include "registry/key_table.h"

namespace cloth {

using ConstraintKey = Key<Constraints>;

const std::vector<ConstraintKey>& constraintKeys();

}  // namespace cloth
