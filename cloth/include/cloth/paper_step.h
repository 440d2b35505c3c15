#pragma once
// The paper's step (Kang & Cho), equation by equation (kangcho/paper_step.cpp): the linearized
// backward Euler system of one step (eqs. 7, 12, 15-17, with the pins eliminated), then dv(0)
// and Jacobi sweeps (eqs. 11, 14). Its system is the one exact, cg and chebyshev solve; kangcho's
// impl=reference is this step.

#include "cloth/system.h"

namespace cloth {

// Builds the system at `state`. Pins with out-of-range particle indices are ignored.
void buildSystem(const StepProblem& problem, LinearSystem& sys);

// Builds the system at `state`, then dv(0) and `iterations` Jacobi sweeps into dv.
void paperStep(const StepProblem& problem, int iterations, LinearSystem& sys, Points& dv);

// One Jacobi sweep: dvNext_i = W_ii^-1 (b_i + h^2 sum_j J_ij dv_j); pinned stay prescribed.
void jacobiSweep(const Model& model, const LinearSystem& sys, const Points& dv, Points& dvNext);
// dv(0)_i = W_ii^-1 b_i (eq. 11, k = 0); pinned get their prescribed dv.
void jacobiStart(const LinearSystem& sys, Points& dv);

}  // namespace cloth
