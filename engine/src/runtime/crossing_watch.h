#pragma once
// The flag's crossings, counted by the cloth library's checker (cloth/crossings.h, which shares no
// code with contact) whenever the frame loop asks (after each frame's ticks, or after every tick):
// edges through the pole's solid or the vehicle's body, particles below the ground, and
// edge-triangle pairs of the flag at least three cells apart. What summary.json and the panel report.

#include <vector>

#include "cloth/crossings.h"
#include "engine/flag/flag.h"

namespace engine {

struct CrossingTally {
    int last = 0;              // the last count's
    int max = 0;               // the most in one count
    long long checks = 0;      // counts made
    long long withAny = 0;     // counts that found any
    cloth::CrossingCounts worst;  // the count with the most, by kind
    cloth::CrossingCounts most;   // the most of each kind in one count (each from its own count)
};

class CrossingWatch {
public:
    // The scene's solids: the pole on `mount` (its sleeve's edges left out while the pinned column
    // runs down its axis), the vehicle's body when given (world box, per tick), the ground plane.
    CrossingWatch(const SceneConfig& scene, const PoleMount& mount, bool ground);
    // Counts the flag's crossings now, with the carrier where it is and the body (if any).
    void count(const Flag& flag, const RigidFrame& carrier, const cloth::Collider* body);
    const CrossingTally& tally() const { return tally_; }

private:
    PoleMount mount_;
    bool ground_ = false;
    std::vector<std::uint8_t> sleeve_;  // the pinned column, when it runs down the pole's axis
    CrossingTally tally_;
};

}  // namespace engine
