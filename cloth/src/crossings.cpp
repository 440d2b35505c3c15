#include "cloth/crossings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "crossings/self.h"
#include "crossings/topology.h"

namespace cloth {

namespace {

using crossings::Edge;

Scalar unitClamp(Scalar v) { return std::clamp(v, Scalar(0), Scalar(1)); }

// Below this squared sine of their angle two segments count as parallel (any s then gives the
// distance of their lines, and the clamps below find the closest pair).
constexpr Scalar kParallel = 1e-14;

// Squared distance of segments p1 + s d1 and p2 + t d2, s, t in [0, 1] (Ericson, Real-Time
// Collision Detection, 5.1.9): with r = p1 - p2, a = d1.d1, b = d1.d2, c = d1.r, e = d2.d2,
// f = d2.r: s = clamp((b f - c e) / (a e - b^2)), t = (b s + f) / e; if t leaves [0, 1] it is
// clamped and s = clamp((t b - c) / a). A segment of zero length is its point.
Scalar segmentDistanceSquared(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
    const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const Scalar a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r), c = d1.dot(r);
    Scalar s = 0, t = 0;
    if (a == 0 && e == 0) {
        // both points: s = t = 0
    } else if (a == 0) {
        t = unitClamp(f / e);
    } else if (e == 0) {
        s = unitClamp(-c / a);
    } else {
        const Scalar b = d1.dot(d2), denom = a * e - b * b;
        s = denom > kParallel * a * e ? unitClamp((b * f - c * e) / denom) : 0;
        t = (b * s + f) / e;
        if (t < 0 || t > 1) {
            t = unitClamp(t);
            s = unitClamp((t * b - c) / a);
        }
    }
    return (r + s * d1 - t * d2).squaredNorm();
}

// Whether the segment pq has a point strictly inside the box. In box coordinates
// y(u) = R^T (p - center) + u R^T (q - p), u in [0, 1], axis i keeps |y_i(u)| < h_i for u in an
// open interval (lo_i, hi_i) (all u or none when the segment is flat along it); the segment
// enters when max lo_i < min hi_i, max lo_i < 1 and min hi_i > 0. A non-finite end enters none.
bool entersBox(const Vec3& p, const Vec3& q, const CrossingScene::Box& box) {
    if (!p.allFinite() || !q.allFinite()) return false;
    const Vec3 y0 = box.rotation.transpose() * (p - box.center);
    const Vec3 d = box.rotation.transpose() * (q - p);
    Scalar lo = -std::numeric_limits<Scalar>::infinity(), hi = std::numeric_limits<Scalar>::infinity();
    for (int i = 0; i < 3; ++i) {
        const Scalar h = box.halfExtents(i);
        if (!(h > 0)) return false;
        if (d(i) == 0) {
            if (!(std::abs(y0(i)) < h)) return false;
            continue;
        }
        const Scalar u0 = (-h - y0(i)) / d(i), u1 = (h - y0(i)) / d(i);
        lo = std::max(lo, std::min(u0, u1));
        hi = std::min(hi, std::max(u0, u1));
    }
    return lo < hi && lo < 1 && hi > 0;
}

// A solid's world bounds, padded by a millionth of its size: an edge whose bounds miss them
// cannot reach inside it.
struct Reach {
    Vec3 lo, hi;
    bool meets(const Vec3& p, const Vec3& q) const {
        return (p.cwiseMin(q).array() <= hi.array()).all() && (lo.array() <= p.cwiseMax(q).array()).all();
    }
};

Reach reachOf(const CrossingScene::Capsule& c) {
    const Vec3 pad = Vec3::Constant(c.radius * (1 + 1e-6));
    return {c.a.cwiseMin(c.b) - pad, c.a.cwiseMax(c.b) + pad};
}

// The box's half size along world axis i: sum over its axes j of |R_ij| h_j.
Reach reachOf(const CrossingScene::Box& b) {
    const Vec3 half = b.rotation.cwiseAbs() * b.halfExtents * (1 + 1e-6);
    return {b.center - half, b.center + half};
}

bool skipped(const std::vector<std::uint8_t>* skip, const Edge& e) {
    return skip != nullptr && ((*skip)[e.p] != 0 || (*skip)[e.q] != 0);
}

// Edges (not skipped) strictly closer than a capsule's radius to its axis segment, once each.
int countPoleEdges(const Points& x, const std::vector<Edge>& edges,
                   const std::vector<CrossingScene::Capsule>& capsules, const std::vector<std::uint8_t>* skip) {
    std::vector<Reach> reach;
    for (const auto& c : capsules) reach.push_back(reachOf(c));
    int count = 0;
    for (const Edge& e : edges) {
        if (skipped(skip, e)) continue;
        const Vec3 p = x.col(e.p), q = x.col(e.q);
        for (std::size_t k = 0; k < capsules.size(); ++k) {
            const auto& c = capsules[k];
            if (c.radius > 0 && reach[k].meets(p, q) &&
                segmentDistanceSquared(p, q, c.a, c.b) < c.radius * c.radius) {
                ++count;
                break;
            }
        }
    }
    return count;
}

// Edges with a point strictly inside a box, once each.
int countBodyEdges(const Points& x, const std::vector<Edge>& edges, const std::vector<CrossingScene::Box>& boxes) {
    std::vector<Reach> reach;
    for (const auto& b : boxes) reach.push_back(reachOf(b));
    int count = 0;
    for (const Edge& e : edges) {
        const Vec3 p = x.col(e.p), q = x.col(e.q);
        for (std::size_t k = 0; k < boxes.size(); ++k)
            if (reach[k].meets(p, q) && entersBox(p, q, boxes[k])) {
                ++count;
                break;
            }
    }
    return count;
}

// Particles with (x - point) . normal < 0 for some plane, once each.
int countGroundParticles(const Points& x, const std::vector<CrossingScene::Plane>& grounds) {
    int count = 0;
    for (Eigen::Index i = 0; i < x.cols(); ++i)
        count += std::any_of(grounds.begin(), grounds.end(),
                             [&](const auto& g) { return (x.col(i) - g.point).dot(g.normal) < 0; });
    return count;
}

}  // namespace

CrossingCounts countCrossings(const Model& model, const Points& x, const CrossingScene& scene,
                              const std::vector<std::uint8_t>* skip) {
    const int n = model.particleCount();
    if (x.cols() != n || (skip != nullptr && int(skip->size()) != n))
        throw std::invalid_argument("countCrossings: positions and skip need one entry per particle (" +
                                    std::to_string(n) + ")");
    const crossings::MeshEdges mesh = crossings::meshEdges(model);
    const std::vector<Edge>& edges = mesh.edges;
    CrossingCounts counts;
    counts.poleEdges = scene.capsules.empty() ? 0 : countPoleEdges(x, edges, scene.capsules, skip);
    counts.bodyEdges = scene.boxes.empty() ? 0 : countBodyEdges(x, edges, scene.boxes);
    counts.groundParticles = countGroundParticles(x, scene.grounds);
    counts.selfEdges = crossings::countSelfCrossings(model, x, mesh);
    return counts;
}

}  // namespace cloth
