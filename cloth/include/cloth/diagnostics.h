#pragma once
// Per-step diagnostics: strain (stretch and compression apart), energies, solve error.

#include "cloth/solver.h"

namespace cloth {

struct Diagnostics {
    Scalar maxStretch = 0, p99Stretch = 0;          // max(L/l0 - 1, 0) over springs
    Scalar maxCompression = 0, p99Compression = 0;  // max(1 - L/l0, 0) over springs
    Scalar kinetic = 0;                             // J
    Scalar potential = 0;                           // springs + gravity (height along -g), J
    bool finite = true;
};

Diagnostics measure(const Model& model, const Environment& env, const State& state,
                    bool structuralOnly = false);

// |dv - dv_exact| / |dv_exact| for the system of the step's problem (its state: before the step).
Scalar solveError(const StepProblem& problem, const Points& dv);

// Index of the first particle with a non-finite position or velocity, or -1.
Index firstNonFinite(const State& state);

}  // namespace cloth

namespace cloth {

// What "stable" means for a run (docs/algorithm.md): finite, positions bounded, strain bounded,
// speeds bounded. Energy growth needs a history and is checked by the caller.
struct StabilityLimits {
    Scalar maxStretch = 1.0;    // a spring at twice its rest length is a blow-up, not cloth
    Scalar maxDistance = 100;   // m from the anchor point
    Scalar maxSpeed = 1000;     // m/s
};

// Null when the state is within the limits, else a short reason.
const char* instability(const Diagnostics& d, const State& state, const Vec3& anchor,
                        const StabilityLimits& limits = {});

}  // namespace cloth
