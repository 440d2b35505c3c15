#pragma once
// The distances the contact stage (contact.h) bounds its moves by: closest points between segments,
// of a point to a triangle, of a point or a segment to a box. Plain functions of their
// arguments.

#include <vector>

#include "cloth/parallel_for.h"
#include "cloth/types.h"

namespace cloth::contact {

struct SegmentPair {
    Scalar s = 0, t = 0;  // parameters of the closest points: p0 + s (p1 - p0), q0 + t (q1 - q0)
    Scalar distance = 0;
};

// The closest points of segments p0-p1 and q0-q1 (parallel and degenerate segments too).
SegmentPair closestSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

struct PointTriangle {
    Vec3 weights = Vec3::Zero();  // barycentric weights of the closest point of the triangle
    Scalar distance = 0;
};

// The closest point of triangle a-b-c to p (Ericson, Real-Time Collision Detection, 5.1.5).
PointTriangle closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// The distance of segment p0-p1 to an oriented box (center, columns of R its axes, half sizes e),
// from below: t -> |p(t) - box| is convex, minimized by golden-section search and lowered by the
// search's remaining interval times the segment's length (the function's Lipschitz constant).
Scalar segmentBoxDistance(const Vec3& p0, const Vec3& p1, const Vec3& center, const Mat3& R, const Vec3& e);

// The distance of a point to an oriented box (0 inside).
Scalar pointBoxDistance(const Vec3& p, const Vec3& center, const Mat3& R, const Vec3& e);

// Each particle's straight move's length, |y1_i - y0_i| (the squares summed x, y, z, as Eigen's
// norm does: the same bits), in a loop the compiler vectorizes.
void moveLengths(const Points& y0, const Points& y1, std::vector<Scalar>& out, ParallelFor* loops = nullptr);

}  // namespace cloth::contact
