#pragma once
// Ready-made cloth set-ups shared by the app, the tests, the benchmark and the study, so that
// every one of them measures the same cloth.

#include <vector>

#include "cloth/model.h"
#include "cloth/system.h"

namespace cloth {

// A flag of nx x ny particles in the vertical x-y plane, its pole-side edge (column 0) pinned
// along a vertical pole whose top is at `poleTop`; the flag extends along +x and hangs under
// gravity from there.
struct HangingFlag {
    Model model;
    State state;
    std::vector<Pin> pins;
};

struct HangingFlagDesc {
    int nx = 33, ny = 33;
    Scalar width = 1.5, height = 1.0, totalMass = 0.3;
    Stiffness stiffness = {1e4, 1e4, 1e3};
    Vec3 poleTop = Vec3(0, 2, 0);
};

HangingFlag makeHangingFlag(const HangingFlagDesc& desc);

// Pins for column 0 of a grid model, at their rest positions moved by `offset`, with velocity v.
std::vector<Pin> pinColumn(const Model& model, const Vec3& offset = Vec3::Zero(),
                           const Vec3& v = Vec3::Zero());

}  // namespace cloth
