// The contact stage's displacement bounds (cloth/contact.h).

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/geometry.h"
#include "contact/work.h"

namespace cloth {

using namespace contact;

// Bounds from the self pairs at the current positions: every particle of a pair under kSelfShare
// of the pair's gap less the floor (boundPair). A pair that separate() did not measure is measured
// only if the bound from its gap's lower bound could bind one of its particles' moves (len): if it
// cannot, the exact bound, which is larger, cannot either, and the pair changes nothing.
void ContactStage::Work::selfBounds() {
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (!fresh[k]) {
            const Scalar longest = std::max({len[ids[k][0]], len[ids[k][1]], len[ids[k][2]], len[ids[k][3]]});
            if (kSelfShare * (gapBound(k) - floor()) >= longest + kSlack) continue;
            const Closest c = closestNow(k);
            measured(k, c.distance, c.normal);
        }
        boundPair(k);
    }
}

// Pair k's bound on its particles: the length of each one's move, or with half-spaces only its move
// towards the other primitive: the first primitive's particles (the vertex, or the first edge's
// ends) along the pair's direction, the second's against it. Touching pairs (no direction) hold
// their particles where they are.
void ContactStage::Work::boundPair(std::size_t k) {
    const Scalar b = kSelfShare * (gap[k] - floor());
    const auto& q = ids[k];
    if (!halfSpaces || gap[k] <= 0) {
        for (Index i : q) limit(i, b);
        return;
    }
    const int first = pairs[k].kind == Pair::Kind::VertexTriangle ? 1 : 2;  // particles of the first primitive
    for (int j = 0; j < 4; ++j) {
        if (invMass[q[j]] == 0) continue;
        keepTo(q[j], j < first ? normal[k] : Vec3(-normal[k]), b);
    }
}

// Bounds from the solids: near a capsule, a half-space per particle (capsuleBounds); near a box, a
// free particle under kSolidShare of its gap to the box, each end of an edge under kSolidShare of
// the edge's gap.
void ContactStage::Work::solidBounds() {
    for (const Near& n : near) {
        const Collider& c = *n.solid;
        if (c.shape == Collider::Shape::Capsule) {
            capsuleBounds(n);
            continue;
        }
        for (Index i : n.vertices)
            limit(i, kSolidShare * (contact::pointBoxDistance(y.col(i), c.center, c.rotation, c.halfExtents) - floor()));
        for (Index e : n.edges) {
            const Index i = (*edges)[e][0], j = (*edges)[e][1];
            const Scalar d = contact::segmentBoxDistance(y.col(i), y.col(j), c.center, c.rotation, c.halfExtents);
            limit(i, kSolidShare * (d - floor())), limit(j, kSolidShare * (d - floor()));
        }
    }
}

// Near a capsule: each free vertex and each end of an edge keeps to the plane through the closest
// point of the capsule's axis, at most kSolidShare of its height over the capsule's offset surface
// (radius + floor) closer to it. The capsule lies within its radius of that plane's back, so a
// straight move of the ends that keeps to it keeps the whole edge out, and the particle slides
// freely along the capsule (a bound on the length of its move would hold a pressed particle still).
// A pinned end stays where it is, on the plane's side: an edge from a pin swings round the capsule
// only as far as the plane of each sub-interval lets its free end.
void ContactStage::Work::capsuleBounds(const Near& n) {
    const Collider& c = *n.solid;
    const std::pair<Vec3, Vec3> axis = axisOf(c);
    const Vec3 &a = axis.first, &b = axis.second;
    auto keepOff = [&](Index i, const Vec3& normal, const Vec3& q) {
        if (invMass[i] == 0) return;
        keepTo(i, normal, kSolidShare * ((y.col(i) - q).dot(normal) - c.radius - floor()));
    };
    // The segment i-j (a vertex: i == j) against the plane through the axis's closest point to it;
    // on the axis there is no plane, and its ends stay where they are.
    auto keepSegmentOff = [&](Index i, Index j) {
        const auto at = contact::closestSegments(y.col(i), y.col(j), a, b);
        if (at.distance <= 0) return limit(i, 0), limit(j, 0);
        const Vec3 p = (1 - at.s) * y.col(i) + at.s * y.col(j), q = (1 - at.t) * a + at.t * b;
        const Vec3 normal = (p - q) / at.distance;
        keepOff(i, normal, q);
        if (j != i) keepOff(j, normal, q);
    };
    for (Index i : n.vertices) keepSegmentOff(i, i);
    for (Index e : n.edges) keepSegmentOff((*edges)[e][0], (*edges)[e][1]);
}

// Particle i's move cut to its half-spaces and its bound: each plane it leaves is met by taking off
// the move's excess across it; if that left another plane, the move is shortened until every plane
// holds (a shorter move in the same direction keeps to every plane the longer one kept to, as each
// allows the particle where it is); then the move is shortened to the bound. True if cut.
bool ContactStage::Work::bounded(Index i, Vec3& move) const {
    bool cut = false;
    for (int k = firstPlane[i]; k >= 0; k = planes[k].next)
        if (const Scalar over = -planes[k].allow - move.dot(planes[k].n); over > 0) move += over * planes[k].n, cut = true;
    Scalar scale = 1;
    for (int k = firstPlane[i]; k >= 0; k = planes[k].next)
        if (const Scalar m = move.dot(planes[k].n); m < -planes[k].allow) scale = std::min(scale, planes[k].allow / -m);
    const Scalar l = scale * move.norm();
    if (l > bound[i]) scale *= bound[i] / l;
    if (scale < 1) move *= scale, cut = true;
    return cut;
}

// Particle i's move cut so that it ends within `thickness` of its straight move in this pass (y0 to
// y1), the region where the broad phase looked for its pairs (contact.h): on its straight move
// plus pushes of at most `thickness` a particle stays there, but sliding along a capsule can take
// it out. The distance to a segment is convex along the move, which starts inside, so bisection
// finds where it leaves; a shorter move keeps to every bound the longer one kept to. True if cut.
bool ContactStage::Work::keepInRegion(Index i, Vec3& move) const {
    const Vec3 a = y0.col(i), d = y1.col(i) - a, p = y.col(i);
    const Scalar dd = d.squaredNorm();
    auto offPath2 = [&](Scalar s) {  // squared
        const Vec3 q = p + s * move - a;
        const Scalar t = dd > 0 ? std::clamp(q.dot(d) / dd, Scalar(0), Scalar(1)) : Scalar(0);
        return (q - t * d).squaredNorm();
    };
    const Scalar r2 = thickness * thickness;
    if (offPath2(1) <= r2 * (1 + kRegionRounding)) return false;
    Scalar in = 0, out = 1;
    for (int k = 0; k < 60; ++k) {
        const Scalar mid = 0.5 * (in + out);
        (offPath2(mid) <= r2 ? in : out) = mid;
    }
    move *= in;
    return true;
}

}  // namespace cloth
