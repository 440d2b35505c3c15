#pragma once
// The linearized system (system.h) solved exactly: what the exact kind, the diagnostics' solve
// error and the tests measure every solver against.

#include "cloth/system.h"

namespace cloth {

// The exact solution of the system: sparse Cholesky with iterative refinement. Returns false when
// the factorization fails or the relative residual stays over `tolerance`.
bool solveExact(const Model& model, const LinearSystem& sys, Points& dv, Scalar* residual = nullptr,
                Scalar tolerance = 1e-10);

}  // namespace cloth
