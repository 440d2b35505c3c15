#pragma once
// What the physics tests share: solvers from spec strings, random vectors, states and pins. The
// tests compare the library against computations written in the tests, independently of it.

#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth/model.h"
#include "cloth/rigid_frame.h"
#include "cloth/solvers/multigrid_settings.h"
#include "cloth/solver.h"
#include "cloth/system.h"

namespace cloth::test {

// The solver of `spec`; a multigrid one with its settled tuning changed by `tune`, where given
// (a test failure, and null, for a spec that does not parse).
std::unique_ptr<Solver> solverFor(const std::string& spec, const std::function<void(MultigridTuning&)>& tune = nullptr);

Vec3 randomVec(std::mt19937& rng, Scalar lo, Scalar hi);
// 64-bit FNV-1a over raw bytes, continuing from `hash` (the golden hashes).
inline std::uint64_t fnv1a(const void* data, std::size_t bytes, std::uint64_t hash = 0xcbf29ce484222325ull) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) hash = (hash ^ p[k]) * 0x100000001b3ull;
    return hash;
}
Points randomPoints(int n, Scalar magnitude, unsigned seed);
inline Eigen::VectorXd flat(const Points& p) { return Eigen::Map<const Eigen::VectorXd>(p.data(), p.size()); }
inline Scalar relativeError(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
    return (got - want).norm() / want.norm();
}

struct Cloth {
    Model model;
    State state;
};
// A grid cloth (column 0 on the pole side) in a random deformed, moving state: positions
// jittered by `jitter` times the spacing (so some springs are stretched and some compressed),
// velocities uniform in [-speed, speed].
Cloth deformedGrid(int nx, int ny, const Stiffness& k, Scalar jitter, Scalar speed, unsigned seed);

// A step's input: its length, pins and external force (may be null).
inline StepInput stepInput(Scalar h, const std::vector<Pin>& pins, const Points* external) {
    StepInput input;
    input.h = h;
    input.pins = pins;
    input.externalForce = external;
    return input;
}

// Pins on column 0 whose targets are off the current positions and move: the general case.
std::vector<Pin> movingPins(const Cloth& c, unsigned seed);

// A carrier moving and turning (3t^2 m along +z, 0.8 rad/s about +y), so that the air, the pins
// and the pole all matter.
RigidFrame turningCarrier(double t);

}  // namespace cloth::test
