#pragma once
// The equations of one implicit step, whatever the integrator: find the velocity v with
//   x(v) = xHat + k v,    R(v) = M (v - vHat) - k f(x(v), v) = 0   (free particles)
// backward Euler:  xHat = x_n, vHat = v_n, k = h
// BDF2:            xHat = (4 x_n - x_{n-1}) / 3, vHat = (4 v_n - v_{n-1}) / 3, k = 2 h / 3
// f: gravity, linear drag, the springs (eq. 15), the caller's external force and, when the step
// couples the air, the air at x(v), v (air.h); else, with input.damping, -C_i (v_i - v_n,i).
// Pinned particles take their target's velocity and sit at pinX, where the integrator puts their
// target at the stage (a pole that jumps moves its pins in the equations, not only after them).

#include <vector>

#include "cloth/air.h"
#include "cloth/system.h"

namespace cloth {

struct StepEquations {
    const Model& model;
    const Environment& env;
    const StepInput& input;  // pins, the external force, the air (input.air)
    Points xHat, vHat;
    Scalar k = 0;
    bool compressionRule = true;
    std::vector<std::pair<Index, Vec3>> pinX;  // the pinned particles' positions at the stage
    const Points* vStart = nullptr;  // v_n: input.damping's forces are -C_i (v_i - v_n,i)
};

// x(v) of every particle of `at` from its velocities: xHat + k v, pinned ones at pinX.
void stagePositions(const StepEquations& eq, State& at);

// The forces f(x, v) of the equations at `at` (air included when input.air is set).
void stepForces(const StepEquations& eq, const State& at, Points& f, ThreadPool* pool, AirWorkspace* workspace);

// R(v) at `at` (whose x is x(v)) from its forces f; zero on pinned particles. Returns
// max_i |R_i| / m_i over free particles (m/s: how far v is from solving the step).
Scalar stepResidual(const StepEquations& eq, const State& at, const Points& f, const std::vector<std::uint8_t>& pinned,
                    Points& residual);

// out = K in with K = df/dx of the springs at positions x (eq. 16, with eq. 17 when
// compressionRule): out_i = sum over springs (i, j) of J_ij (in_j - in_i).
void springStiffnessTimes(const Model& model, const Points& x, bool compressionRule, const Points& in, Points& out);

}  // namespace cloth
