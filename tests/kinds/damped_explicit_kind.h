#pragma once
// A test's own solver kind (damped_explicit_kind.cpp), registered by the tests that use it.

#include "cloth/solver_kind.h"

namespace cloth {

inline constexpr const char* kDampedExplicit = "damped_explicit";

SolverKind dampedExplicitKind();

// Registers the kind once per process (the tests of one executable may each ask).
inline void registerDampedExplicit() {
    if (!findSolverKind(kDampedExplicit)) registerSolverKind(dampedExplicitKind());
}

}  // namespace cloth
