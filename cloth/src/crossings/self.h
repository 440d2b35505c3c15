#pragma once
// Self crossings for the crossing checker (cloth/crossings.h): mesh edges that properly cross
// triangles at least three cells away, with a broad phase.

#include "cloth/model.h"
#include "crossings/topology.h"

namespace cloth::crossings {

// Whether segment pq properly crosses triangle abc: p and q strictly on opposite sides of the
// plane of abc, and the line pq strictly inside the triangle (exact signs: orient.h).
bool properlyCrosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

// The number of (mesh edge, triangle) pairs that are at least three cells apart (Apartness) and
// properly cross, for positions x. An element with a non-finite coordinate is in no pair.
//
// Broad phase. Units: triangles 2k and 2k + 1 together when they share an edge (a grid's cell),
// else one triangle each, with the edges listed under their triangles (MeshEdges). Each finite
// unit's bounding box is listed in the cells it overlaps of a uniform grid of cubes, whose side
// is the mean length of the finite edges, hashed into buckets. A unit meets the units before it
// in the cells it overlaps, each in the first cell both boxes share only. A pair all near each
// other (Apartness::allNear) or whose boxes do not overlap ends there; otherwise each edge of one
// whose box overlaps a triangle of the other is judged against it. A unit whose box spans more
// than 64 cells is kept out of the grid and meets every other unit instead, so no pair is missed
// and a stray particle does not flood the grid.
int countSelfCrossings(const Model& model, const Points& x, const MeshEdges& mesh);

}  // namespace cloth::crossings
