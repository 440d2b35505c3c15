#pragma once
// Contact: after a step, no edge of the cloth ends up through a solid its carrier holds (the pole,
// the vehicle's body) or through another part of the cloth, whatever the step's length or speed.
// It runs outside any solver's linear solve, as a game engine would add it to the paper's step,
// on the step's start and end positions, in the carrier's frame (so that the solids stand still
// and a teleport of the carrier moves nothing):
//
//   1. broad phase (contact/broad_phase.h): the primitives whose swept boxes can meet, self pairs
//      (vertex-triangle and edge-edge, more than two grid cells apart) and the primitives near
//      each solid;
//   2. the step's motion of those particles cut into sub-intervals of at most `maxMove` each;
//      in each, the particles head for their share of the step's end, and
//      - proximity: pairs that would come closer than `thickness` are pushed apart (position
//        corrections along the pair's normal, as position-based dynamics does), and edges are
//        kept `thickness` off a capsule's surface;
//      - displacement bounds (the guarantee, after Offset Geometric Contact, Chen et al. 2025):
//        each particle moves at most 0.9 times half its distance to any other part of the cloth
//        it may meet (0.9 times the whole distance to a box): two primitives each moving less than
//        half the gap between them cannot meet, so no edge crosses a triangle or a box during the
//        sub-interval. With SelfBounds::HalfSpaces a self pair bounds only each particle's move
//        towards the other primitive, along the direction between the pair's closest points: two
//        convex primitives lie on either side of the slab between those points, each moves less
//        than half the slab's width towards the other, so the slab's middle plane still parts them. Near a capsule the bound has a direction: a particle approaches the plane
//        through the capsule's closest point by at most 0.9 times its height over the capsule's
//        surface, and slides along it freely (the capsule lies behind that plane, so nothing
//        on the plane's side reaches it; a bound on the whole move held pressed particles still).
//   3. the positions back in the world, each particle's velocity changed by its correction / h.
// A step with more self pairs than it can bound in reasonable time (ContactReport::overloaded)
// leaves the free particles where its pass started (the first: the step's start in the carrier's frame).
// The state is never left crossed if it started uncrossed. Pinned particles are never moved.
// Passes: the broad phase looks for a particle's pairs within `thickness` of its straight move (its
// region). Straight moves plus pushes of at most `thickness` stay there; sliding along a capsule
// can leave it, and an unsearched part of the cloth may stand there. A move that would leave is cut
// back to the region's edge (ContactReport::regionCuts), the pass stops after that sub-interval, and
// the next pass (ContactReport::passes) starts from there with its own broad phase, toward the same
// end: the step is then several shorter ones, each guaranteed. After eight such restarts a
// particle at the edge of its region stays there.

#include <cstdint>
#include <memory>
#include <vector>

#include "cloth/collision.h"
#include "cloth/model.h"
#include "cloth/rigid_frame.h"
#include "cloth/parallel_for.h"

namespace cloth {

namespace contact {
class BroadPhase;
}

struct ContactSettings {
    bool enabled = false;      // keep the cloth out of its carrier's solids (and, with self, out of itself)
    bool self = true;          // self-contact (off for a flag that cannot fold onto itself)
    Scalar thickness = 0.005;  // m: the gap kept between two parts of the cloth, and off a capsule
    Scalar maxMove = 0.0025;   // m: the most a particle moves, relative to the carrier, in a sub-interval
    // Inside a solver that takes substeps (small_steps): after every this many substeps and after
    // the last (the motion since the last contact at once); 0: once after the whole step. Solvers
    // without substeps run it once after the step.
    int substepStride = 1;
    // m: with substepStride > 0, inside a solver whose substeps keep its particles' moves relative
    // to the pole short (small_steps): contact after a substep only once both substepStride
    // substeps and this move of the fastest particle relative to the pole (its speed relative to
    // the pole's times each substep's length, summed) have passed since the last contact, and
    // after the last. A carrier at speed takes many substeps for its pins' moves while the cloth
    // hardly moves on it: contact then runs as often as the cloth's own motion asks. 0: by
    // substepStride alone.
    Scalar strideMove = 0;
    // How a self pair bounds its particles: the length of each one's move (Lengths), or only its
    // move towards the other primitive, across the plane that separates them (HalfSpaces), so that
    // layers pressed together slide along each other. Contact once over a whole tick needs it:
    // there a length bound holds pressed layers still while the springs pull their neighbours on.
    enum class SelfBounds : std::uint8_t { Lengths, HalfSpaces } selfBounds = SelfBounds::Lengths;
};

// What one application found and did (or several, summed: long long for a whole run's).
struct ContactReport {
    long long applications = 0;  // apply() calls: 1 for one application
    long long subintervals = 0;  // the step's motion cut into this many (over all its passes)
    long long selfPairs = 0;     // self pairs within reach (when overloaded: the broad phase's candidates)
    long long near = 0;          // vertices and edges near a solid
    long long limited = 0;       // particle moves cut short by their bounds, summed over sub-intervals
    long long regionCuts = 0;    // particle moves cut back to the region their pass searched (sliding on a capsule)
    long long passes = 0;        // passes after the first (each after a region cut; at most 8 a step)
    // Applications with more self pairs than 128 per particle (a cloth blown apart by an unstable
    // solver, or thrown 1 m by a teleport): too many to bound, so the free particles kept their
    // start in the carrier's frame, which is uncrossed (the cloth moved with its carrier).
    long long overloaded = 0;
    // Milliseconds in the broad phase (the pairs and the solids' primitives each pass gathers,
    // the pairs' distances at its start included); the rest of the application's time is its
    // sub-intervals' pushes and bounds.
    double broadPhaseMs = 0;
    ContactReport& operator+=(const ContactReport& r) {  // two applications' work together
        applications += r.applications, subintervals += r.subintervals, selfPairs += r.selfPairs, near += r.near;
        limited += r.limited;
        regionCuts += r.regionCuts, passes += r.passes, overloaded += r.overloaded;
        broadPhaseMs += r.broadPhaseMs;
        return *this;
    }
};

class ContactStage {
public:
    ContactStage();
    ~ContactStage();
    ContactStage(ContactStage&&) noexcept;
    ContactStage& operator=(ContactStage&&) noexcept;

    // The step from `xStart` (world, the carrier at `from`) to `state` (the carrier at `to`):
    // `solids` are in the carrier's frame (capsules and boxes; their radius and half sizes the
    // solid itself). `pinned[i] != 0`: a pinned particle. Changes state.x and state.v. `loops`,
    // if given, runs the broad phase's passes over the whole cloth (the frames, the boxes, the
    // normal cones) on its threads: the same bits as without.
    ContactReport apply(const Model& model, const std::vector<std::uint8_t>& pinned, const Points& xStart,
                        State& state, const RigidFrame& from, const RigidFrame& to, const std::vector<Collider>& solids,
                        const ContactSettings& settings, Scalar h, ParallelFor* loops = nullptr);

private:
    struct Work;
    std::unique_ptr<contact::BroadPhase> broad_;
    std::unique_ptr<Work> work_;
};

}  // namespace cloth
