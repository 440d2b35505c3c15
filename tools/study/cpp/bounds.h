#pragma once
// The bounds a configuration must keep against its flag's fine-step reference (the same for both
// flags):
//   p99 stretch   at most 1.25 x the reference's + 1 point
//   peak stretch  at most 1.5 x the reference's + 2 points
//   energy        the last second's kinetic energy at the scale of 8x8 patches 0.5-2 x the
//                 reference's, on the paths where the air keeps the flag fluttering (flutter)
//   unstable      not finite and bounded, or a failed step (extreme_runs.h)

#include <string>

#include "extreme_cases.h"
#include "extreme_runs.h"

namespace study {

constexpr double kP99Factor = 1.25, kP99Points = 0.01, kPeakFactor = 1.5, kPeakPoints = 0.02;
constexpr double kEnergyLow = 0.5, kEnergyHigh = 2;

// The bounds `run` misses against `reference` on path x: "" (none), "unstable", or some of "p99",
// "peak", "energy", ';'-separated in that order.
std::string missedBounds(const ExtremeRun& run, const ExtremeRun& reference, const Extreme& x);

}  // namespace study
