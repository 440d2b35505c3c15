#pragma once
// How many substeps keep symplectic Euler stable on a cloth: h_sub < 2 / (w_max + c_max), with
// w_max^2 <= max_i 2 sum_j k_ij / m_i (Gershgorin's bound on the springs' M^-1 K) and c_max the
// largest rate at which the air takes a particle's velocity, max_i |df_i/dv_i| / m_i, bounded per
// triangle by rho / 4 (2 |c_d| + 3 |c_f| + 4 |c_l|) |N| s / 9 (air.h's force, its derivative in
// the relative air velocity w, a third of each triangle to a corner, a third of w from each).

#include <vector>

#include "cloth/air.h"
#include "cloth/model.h"
#include "cloth/system.h"

namespace cloth {

// w_max: the springs' bound, once per model.
Scalar springFrequencyBound(const Model& model);

// c_max at this state (0 without air).
Scalar airRateBound(const Model& model, const State& state, const AirParams* air);

// The substeps of a step h: the fewest whose length is at most `fraction` of 2 / (w + c).
int stableSubsteps(Scalar h, Scalar springFrequency, Scalar airRate, Scalar fraction);

// The largest distance a point moves in a step h: a pin on its straight line from start to end,
// or a particle at its velocity relative to `frame` (the pole's velocity).
Scalar largestMove(const std::vector<Vec3>& start, const std::vector<Vec3>& end, const State& state,
                   const Vec3& frame, Scalar h);

// The fewest substeps that split `move` into pieces of at most maxMove (0 when maxMove is 0).
int pacedSubsteps(Scalar move, Scalar maxMove);

}  // namespace cloth
