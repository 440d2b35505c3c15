#pragma once
// A crossing checker: counts where a state of the cloth passes through its pole, the vehicle's
// body, the ground or itself. It judges positions alone and shares no code with the collision
// response (collision.h): its geometry is its own, so it can check that code's results.
//
// What is counted, for positions x of a model:
// - Mesh edges: the unique edges of model.triangles() (the springs play no part).
// - poleEdges: mesh edges whose segment comes strictly closer than a capsule's radius to the
//   capsule's axis segment (segment-to-segment distance; a point-like axis is a sphere). An edge
//   touching two capsules counts once. Edges with an end marked in `skip` are left out.
// - bodyEdges: mesh edges with a point strictly inside a box (the open box: touching a face,
//   an edge or a corner is not inside). An edge inside two boxes counts once.
// - groundParticles: particles with (x - point) . normal < 0 for some ground plane (the solid
//   is on the side opposite to the normal; the normal need not be unit). Counted once each.
// - selfEdges: pairs (mesh edge pq, triangle abc) where pq properly crosses abc: p and q are
//   strictly on opposite sides of the triangle's plane and the crossing point is strictly inside
//   the triangle. Touching (p or q on the plane, or the segment through the triangle's boundary)
//   is not a crossing. Only pairs at least three cells apart are judged: on a grid model
//   (gridNx() > 0; particle i at column i % nx, row i / nx), every pair (u of the edge, w of the
//   triangle) has max(|row_u - row_w|, |col_u - col_w|) >= 3; on any other model, every such
//   pair is at least 3 edges apart in the mesh graph (they share no vertex, and no vertex of one
//   is within 2 edges of a vertex of the other).
//   The sides are signs of orient3d determinants, settled exactly: a filtered long double
//   evaluation, and exact expansion arithmetic when its result is within the filter's error
//   bound of zero (cloth/src/crossings/orient.h). Exact for every finite double input.
// - Non-finite positions are never counted (nothing can be judged about them).
//
// Self crossings have a broad phase (a uniform hash grid of triangle bounds, its cell the mean
// edge length), so a flat 65 x 65 flag is checked in a fraction of a millisecond. The result does
// not depend on the order of the work: each count is a number of pairs or elements.

#include <cstdint>
#include <vector>

#include "cloth/model.h"

namespace cloth {

// What a state is checked against, in world space.
struct CrossingScene {
    // A solid capsule: the points within `radius` of the axis segment a-b (the pole's own radius,
    // not a collision shell).
    struct Capsule { Vec3 a = Vec3::Zero(), b = Vec3::Zero(); Scalar radius = 0; };
    std::vector<Capsule> capsules;
    // An oriented box (the vehicle's body): the columns of `rotation` are its axes in world space.
    struct Box { Vec3 center = Vec3::Zero(); Mat3 rotation = Mat3::Identity(); Vec3 halfExtents = Vec3::Zero(); };
    std::vector<Box> boxes;
    // Solid below the plane: on the side opposite to the normal.
    struct Plane { Vec3 point = Vec3::Zero(), normal = Vec3::UnitY(); };
    std::vector<Plane> grounds;
};

struct CrossingCounts {
    int poleEdges = 0;        // mesh edges closer than a capsule's radius to its axis segment
    int selfEdges = 0;        // (edge, triangle) pairs, at least 3 cells apart, that properly cross
    int bodyEdges = 0;        // mesh edges with a point strictly inside a box
    int groundParticles = 0;  // particles strictly below a ground plane
    int total() const { return poleEdges + selfEdges + bodyEdges + groundParticles; }
};

// Counts the crossings of positions x (3 x model.particleCount()) of `model` against `scene`.
// `skip[i] != 0` marks particles whose incident edges are not counted against capsules (none when
// null; otherwise one entry per particle).
CrossingCounts countCrossings(const Model& model, const Points& x, const CrossingScene& scene,
                              const std::vector<std::uint8_t>* skip = nullptr);

}  // namespace cloth
