#pragma once
// The first part of the study's scenes (part 1, the solve error): the study's flag on a pole that
// is fixed (hanging_flag) or carried along the path the demo's Bullet vehicle drives under the
// drive script (vehicle_path), and the pins and start state on that pole.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth/presets.h"
#include "cloth/system.h"

namespace study {

using cloth::Vec3;

// A pole pose over time: position and velocity of its top, and its rotation (the flag's
// pinned column hangs from the top along the pole).
struct PolePath {
    std::vector<Eigen::Isometry3d> pose;  // per step of the finest h used with it
    std::vector<Vec3> linear, angular;
    double dt = 0;
};

// The chassis path of the demo's drive script, from the demo's own vehicle (Bullet), sampled
// every 1/960 s for `duration` seconds.
PolePath drivePath(double duration);

struct Scene {
    std::string name;
    const PolePath* path = nullptr;  // null: fixed pole
};

// Pins of column 0 for the carrier pose at time t (rest positions in the carrier frame).
std::vector<cloth::Pin> pinsAt(const cloth::Model& m, const Scene& s, double t);

// The flag at rest on the pole's start pose.
cloth::State startState(const cloth::Model& m, const Scene& s);

// The study's flag: n x n, structural and shear stiffness k, bend k/10 (the rest as
// cloth::HangingFlagDesc says).
cloth::HangingFlag studyFlag(int n, double k);

}  // namespace study
