#pragma once
// Anti-stretch: strain limiting in the manner of Provot 1995 ("Deformation constraints in a
// mass-spring model to describe rigid cloth behavior"). After a step, every spring stretched
// beyond (1 + maxStretch) times its rest length has its ends pulled together to that length
// (split by inverse mass; pinned ends do not move), for a few Gauss-Seidel passes in spring order
// (deterministic). The velocity of each moved particle changes by its correction / h, so the
// constraint also removes the stretching velocity.

#include <vector>

#include "cloth/model.h"

namespace cloth {

// Returns the number of corrections applied. `pinned[i] != 0` marks particles that must not move.
int limitStretch(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                 Scalar h, State& state);

}  // namespace cloth
