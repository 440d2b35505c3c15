#pragma once
// The broad phase's normal cones (broad_phase.h) as loops over arrays, which the compiler
// vectorizes: each triangle's cone over a step's motion, and each triangle's widest angle to its
// leaf's axis. Each lane rounds as the scalar formula in the comments (the library is built
// without contraction, simd.h), so the cones have the same bits as computed one at a time.

#include <cmath>
#include <vector>

#include "cloth/model.h"
#include "cloth/parallel_for.h"
#include "simd.h"

namespace cloth::contact {

// Cones as arrays: axis (x, y, z) and the cosine of the half-angle.
struct Cones {
    std::vector<Scalar> x, y, z, cosHalf;
    void resize(std::size_t n) { x.resize(n), y.resize(n), z.resize(n), cosHalf.resize(n); }
    Vec3 axis(std::size_t i) const { return {x[i], y[i], z[i]}; }
};

// Triangles as arrays of their corners: triangle t is (a[t], b[t], c[t]).
struct Corners {
    std::vector<Index> a, b, c;
    void add(const Triangle& t) { a.push_back(t[0]), b.push_back(t[1]), c.push_back(t[2]); }
    void clear() { a.clear(), b.clear(), c.clear(); }
    std::size_t size() const { return a.size(); }
};

// The loops' inputs as arrays (kept between calls so that they are not reallocated).
struct ConeScratch {
    std::vector<Scalar> mx, my, mz;  // motionCones: each particle's midpoint
    std::vector<Scalar> ux, uy, uz;  // widestToAxes: each cone's group's axis
};

// Every triangle's cone over the step from y0 to y1, whatever path each corner takes within
// reach[i] of the midpoint of its straight move: with edges a, b at the midpoint and each edge
// moving at most the sum of its ends' reaches (da, db), the normal a x b moves at most
// e = da |b| + |a| db + da db, so it stays within asin(e / |a x b|) of the midpoint's normal. A
// triangle that could flip (e >= |a x b|) holds every direction (axis +z, cosHalf -1).
void motionCones(const Points& y0, const Points& y1, const std::vector<Scalar>& reach, const Corners& triangles,
                 ConeScratch& scratch, Cones& out, ParallelFor* loops = nullptr);

// The cosine of the widest angle to an axis of a cone whose axis has the cosine `dot` to it and
// whose half-angle has the cosine `cc`: cos(t + w) = cos t cos w - sin t sin w, with no inverse
// cosine; -1 where the sum reaches pi (every direction). Written with selects, so that it
// vectorizes in a loop.
CLOTH_INLINE inline Scalar widestCos(Scalar dot, Scalar cc) {
    const Scalar ct = dot < -1 ? Scalar(-1) : 1 < dot ? Scalar(1) : dot;
    const Scalar cw = cc < -1 ? Scalar(-1) : 1 < cc ? Scalar(1) : cc;
    const bool all = ct <= -cw;
    const Scalar product = all ? Scalar(0) : (1 - ct * ct) * (1 - cw * cw);
    return all ? Scalar(-1) : ct * cw - std::sqrt(product);
}

// The cone holding two cones (axis, cos of half-angle): its axis the normalized sum, its angle
// the larger of each cone's angle plus its axis's angle to the new one. In cosines, with no inverse
// cosine: cos(t + w) = cos t cos w - sin t sin w, and a sum that reaches pi holds every direction.
void mergeCones(const Vec3& a, Scalar ca, const Vec3& b, Scalar cb, Vec3& axis, Scalar& cosHalf);

// For a cone of half-angle w within acos(flat) (its cosine cc > flat): the cosine of the widest
// angle between its axis and another's, of a cone no wider, at which the two merged stay within
// acos(flat). The merged cone's half-angle is half the angle between the axes plus the wider
// cone's, so the angle is 2 (acos(flat) - w), and its cosine 2 cos^2(acos(flat) - w) - 1 with
// cos(acos(flat) - w) = flat cc + sqrt(1 - flat^2) sqrt(1 - cc^2). Where cc <= flat: 2, which
// no cosine exceeds.
Scalar partnerCos(Scalar cc, Scalar flat);

// Whether two cones merged (mergeCones) lie within acos(flat) of their axis, with each cone's
// partnerCos: when both are within it, from the axes' cosine a . b against the wider cone's
// partnerCos, where the two differ by more than kDecided; else, and near that bound, from
// mergeCones itself. Rounding moves a . b and partnerCos by about 1e-15 and mergeCones' cosine
// by at most 1e-8 (a square root's slope near an angle of zero): far under kDecided, so both
// give the same answer.
inline constexpr Scalar kDecided = 1e-6;
bool mergedWithin(const Vec3& a, Scalar ca, Scalar pa, const Vec3& b, Scalar cb, Scalar pb, Scalar flat);

// The cones in groups: group j is cones [start[j], start[j + 1]), with the axis axes[j]. For cone
// k, the cosine of its widest angle to its group's axis (widestCos), written to widest[k].
void widestToAxes(const Cones& cones, const std::vector<std::size_t>& start, const std::vector<Vec3>& axes,
                  ConeScratch& scratch, std::vector<Scalar>& widest, ParallelFor* loops = nullptr);

}  // namespace cloth::contact
