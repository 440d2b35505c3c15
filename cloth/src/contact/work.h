#pragma once
// The contact stage's working state (cloth/contact.h), shared by its parts: the stage's flow
// (contact.cpp), its bounds (bounds.cpp) and its proximity pushes (proximity.cpp).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "cloth/contact.h"
#include "contact/broad_phase.h"

namespace cloth {
namespace contact {

inline constexpr Scalar kSelfShare = 0.45;   // of a self pair's gap: each side moves under half of it
inline constexpr Scalar kSolidShare = 0.9;   // of a gap to a solid, which does not move
// Of the thickness: the gap the bounds share out is the distance less this floor, so no gap ever
// closes below it. Shares of the whole distance would let a pressed pair close 90% of what is
// left in every sub-interval, down to a gap that the round trip into the carrier's frame and back
// (a rounding of 1e-16 m) flips into a crossing.
inline constexpr Scalar kFloor = 0.1;
inline constexpr int kMaxSubintervals = 64;  // beyond it the sub-intervals' moves grow: the bounds still hold
// Self pairs per particle beyond which a step is too many to bound (ContactReport::overloaded): its
// free particles keep their start in the carrier's frame, which is uncrossed. A cloth blown apart
// by an unstable solver has 765 per particle (seconds a tick to bound), a flag thrown 1 m by a
// teleport more than 128 at 33x33 (minutes); the demo's flag folded in the hard brake has 33.
inline constexpr std::size_t kMaxPairsPerParticle = 128;
// A pass stopped at the edge of a particle's region is followed by another toward the same end
// (contact.h), at most this many times a step; in the last, a particle at the edge stays there.
inline constexpr int kMaxRestarts = 8;
// A particle is cut back to its region only past this share beyond it: a push of exactly
// `thickness` across its path (pushes are capped there) ends on the edge, give or take rounding.
inline constexpr Scalar kRegionRounding = 1e-9;
// m: a pair is left unmeasured only when its lower bound clears what it is compared with by this
// much, far above the rounding of the bound (1e-16 m), so that its exact distance would have
// changed nothing (contact.h: the same moves, bit for bit).
inline constexpr Scalar kSlack = 1e-9;

// A solid's primitives near the cloth in this step.
struct Near {
    const Collider* solid = nullptr;
    std::vector<Index> vertices, edges;
};

// A capsule's axis segment.
inline std::pair<Vec3, Vec3> axisOf(const Collider& c) {
    const Vec3 half = std::abs(c.halfExtents.x()) * c.axis;
    return {c.center - half, c.center + half};
}

}  // namespace contact

struct ContactStage::Work {
    Points y0, y1, y, target;  // the pass's start, the step's end (carrier frame), now, the targets
    std::vector<Scalar> bound, invMass;
    std::vector<std::uint8_t> active;
    std::vector<std::uint8_t> pushed;  // free particles that contact may push off their straight moves
    std::vector<Index> moving;  // the active free particles, in increasing order
    std::vector<Index> touched;  // the active and the pinned particles, in increasing order: all a sub-interval moves
    std::vector<contact::Pair> pairs;
    std::size_t candidates = 0;  // the broad phase's candidates when too many (overloaded)
    std::vector<std::array<Index, 4>> ids;  // each pair's particles: the vertex and the triangle's, or both edges'
    std::vector<Scalar> gap;                // each self pair's distance when last measured
    std::vector<std::array<Scalar, 4>> snap;  // its particles' travel then
    std::vector<std::uint8_t> fresh;        // measured in this sub-interval
    std::vector<Scalar> travel;             // each particle's path length so far in this step
    std::vector<Scalar> need, len;          // each particle's move to its target, before and with its pushes
    std::vector<contact::Near> near;
    const Model* model = nullptr;
    ParallelFor* loops = nullptr;  // the application's passes over the whole cloth run on it (or null)
    const std::vector<std::array<Index, 2>>* edges = nullptr;
    Scalar thickness = 0;
    bool halfSpaces = false;                 // self pairs bound by half-spaces (ContactSettings::selfBounds)
    std::vector<Vec3> normal;                // each self pair's direction from its second primitive to its first, when measured

    Points push;                   // this sub-interval's proximity pushes, at most `thickness` each
    std::vector<Scalar> reachOf;   // each particle's move over the pass
    std::vector<std::uint8_t> moved;  // free particles moved in some pass: placed back in the world

    Scalar floor() const { return contact::kFloor * thickness; }
    // A pair's approach from per-particle moves m: the vertex's plus the farthest of the triangle's
    // corners, or the farthest end of each edge (a point of a triangle or of a segment moves at most
    // as far as its farthest corner).
    template <class F>
    Scalar approach(std::size_t k, F m) const {
        const auto& q = ids[k];
        if (pairs[k].kind == contact::Pair::Kind::VertexTriangle) return m(0, q[0]) + std::max({m(1, q[1]), m(2, q[2]), m(3, q[3])});
        return std::max(m(0, q[0]), m(1, q[1])) + std::max(m(2, q[2]), m(3, q[3]));
    }
    // A lower bound of pair k's distance now: its last measured gap less its particles' travel since.
    Scalar gapBound(std::size_t k) const {
        return gap[k] - approach(k, [&](int j, Index i) { return travel[i] - snap[k][j]; });
    }
    void measured(std::size_t k, Scalar distance, const Vec3& n) {
        gap[k] = distance, fresh[k] = 1, normal[k] = n;
        for (int j = 0; j < 4; ++j) snap[k][j] = travel[ids[k][j]];
    }
    // A self pair's closest points: their distance, its four particles' weights in the first
    // primitive's point less the second's (the vertex and the triangle's corners: 1, -w; the
    // edges' ends: 1 - s, s, -(1 - t), -t), and that difference's direction (zero where they touch).
    struct Closest {
        Scalar distance = 0;
        std::array<Scalar, 4> weights{};
        Vec3 normal = Vec3::Zero();
    };
    Closest closestNow(std::size_t k) const;
    Vec3 separation(std::size_t k, const Closest& c, const Points& at) const;
    void boundPair(std::size_t k);
    void limit(Index i, Scalar b) { bound[i] = std::min(bound[i], std::max(Scalar(0), b)); }
    // A half-space a particle's move m keeps to: m . n >= -allow (allow >= 0). A capsule lies
    // behind the plane through its closest point to a primitive, so a move that keeps to it keeps
    // the primitive out, wherever it slides along the plane.
    struct Plane {
        Vec3 n;
        Scalar allow;
        int next;  // the particle's next plane, or -1
    };
    std::vector<Plane> planes;
    std::vector<int> firstPlane;  // each particle's first plane, or -1
    void keepTo(Index i, const Vec3& n, Scalar allow) {
        planes.push_back({n, std::max(Scalar(0), allow), firstPlane[i]});
        firstPlane[i] = int(planes.size()) - 1;
    }
    void capsuleBounds(const contact::Near& n);
    bool bounded(Index i, Vec3& move) const;
    bool keepInRegion(Index i, Vec3& move) const;
    bool mayMeet(contact::Pair& p) const;
    std::array<Index, 4> particlesOf(const contact::Pair& p) const;
    void selfBounds();
    void solidBounds();
    void separate();
    void pushApart(const Index* ids, const Scalar* weights, int n, const Vec3& normal, Scalar gap);
    void toCarrier(const Points& xStart, const State& state, const RigidFrame& from, const RigidFrame& to);
    void gather(contact::BroadPhase& broad, const std::vector<std::uint8_t>& pinned, const std::vector<Collider>& solids,
                const ContactSettings& settings, ContactReport& report);
    bool selfPairs(contact::BroadPhase& broad, const std::vector<std::uint8_t>& pinned);
    Scalar markActive(const std::vector<std::uint8_t>& pinned);
    bool pass(const std::vector<std::uint8_t>& pinned, const ContactSettings& settings, bool last, ContactReport& report);
    void straight(Scalar f);
    bool advance(Scalar f, const std::vector<std::uint8_t>& pinned, ContactReport& report);
};

}  // namespace cloth
