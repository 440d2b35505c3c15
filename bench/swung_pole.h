#pragma once
// The benchmarks' flag: a hanging flag (cloth/presets.h) pinned along column 0, on a pole that
// stands still or, swung, moves on a horizontal circle of radius 0.15 m at 2 Hz (2.4 g) through
// the flag's plane and across it (the flag hangs in x-y), so that the flag flaps and stretches in
// every step, as on the demo's vehicle.

#include <memory>

#include "cloth/presets.h"
#include "cloth/solver.h"

namespace bench {

constexpr double kH = 1.0 / 240;  // the benchmarks' step

enum class Pole { Still, Swung };

// A hanging flag of n x n particles.
cloth::HangingFlag flagOfSize(int n);

// Where the swung pole stands at step s (t = s h), relative to its start, and its velocity.
cloth::Vec3 poleOffset(int s);
cloth::Vec3 poleVelocity(int s);

// The input of step s: the flag's own pins, or pins moved with the swung pole.
cloth::StepInput inputOfStep(const cloth::HangingFlag& flag, Pole pole, int s);

// The demo's solver (the paper's step in float) with `constraints` (cloth/constraints.h's text).
std::unique_ptr<cloth::Solver> demoSolver(const char* constraints);

// Steps [from, to) of `solver` on `flag`, its pole moving as `pole`.
void run(cloth::Solver& solver, cloth::HangingFlag& flag, Pole pole, int from, int to);

}  // namespace bench
