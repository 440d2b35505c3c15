#include "cloth/contact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "contact/broad_phase.h"
#include "contact/geometry.h"

namespace cloth {

using contact::Pair;

namespace {

constexpr Scalar kSelfShare = 0.45;   // of a self pair's gap: each side moves under half of it
constexpr Scalar kSolidShare = 0.9;   // of a gap to a solid, which does not move
// Of the thickness: the gap the bounds share out is the distance less this floor, so no gap ever
// closes below it. Shares of the whole distance would let a pressed pair close 90% of what is
// left in every sub-interval, down to a gap that the round trip into the carrier's frame and back
// (a rounding of 1e-16 m) flips into a crossing.
constexpr Scalar kFloor = 0.1;
constexpr int kMaxSubintervals = 64;  // beyond it the sub-intervals' moves grow: the bounds still hold
// Self pairs per particle beyond which a step is too many to bound (ContactReport::overloaded): its
// free particles keep their start in the carrier's frame, which is uncrossed. A cloth blown apart
// by an unstable solver has 765 per particle (seconds a tick to bound), a flag thrown 1 m by a
// teleport more than 128 at 33x33 (minutes); the demo's flag folded in the hard brake has 33.
constexpr std::size_t kMaxPairsPerParticle = 128;
// m: a pair is left unmeasured only when its lower bound clears what it is compared with by this
// much, far above the rounding of the bound (1e-16 m), so that its exact distance would have
// changed nothing (contact.h: the same moves, bit for bit).
constexpr Scalar kSlack = 1e-9;

// A solid's primitives near the cloth in this step.
struct Near {
    const Collider* solid = nullptr;
    std::vector<Index> vertices, edges;
};

contact::Box boxOf(const Collider& c, Scalar margin) {
    contact::Box b;
    if (c.shape == Collider::Shape::Capsule) {
        const Vec3 half = std::abs(c.halfExtents.x()) * c.axis;
        b.add(c.center - half), b.add(c.center + half);
        b.lo.array() -= c.radius, b.hi.array() += c.radius;
    } else {  // a box: the corners' extent along the world axes
        const Vec3 extent = c.rotation.cwiseAbs() * c.halfExtents;
        b.add(c.center - extent), b.add(c.center + extent);
    }
    b.lo.array() -= margin, b.hi.array() += margin;
    return b;
}

// A capsule's axis segment.
std::pair<Vec3, Vec3> axisOf(const Collider& c) {
    const Vec3 half = std::abs(c.halfExtents.x()) * c.axis;
    return {c.center - half, c.center + half};
}

}  // namespace

struct ContactStage::Work {
    Points y0, y1, y, target;
    std::vector<Scalar> bound, invMass;
    std::vector<std::uint8_t> active;
    std::vector<std::uint8_t> pushed;  // free particles that contact may push off their straight moves
    std::vector<Index> moving;  // the active free particles, in increasing order
    std::vector<Index> touched;  // the active and the pinned particles, in increasing order: all a sub-interval moves
    std::vector<Pair> pairs;
    std::size_t candidates = 0;  // the broad phase's candidates when too many (overloaded)
    std::vector<std::array<Index, 4>> ids;  // each pair's particles: the vertex and the triangle's, or both edges'
    std::vector<Scalar> gap;                // each self pair's distance when last measured
    std::vector<std::array<Scalar, 4>> snap;  // its particles' travel then
    std::vector<std::uint8_t> fresh;        // measured in this sub-interval
    std::vector<Scalar> travel;             // each particle's path length so far in this step
    std::vector<Scalar> need, len;          // each particle's move to its target, before and with its pushes
    std::vector<Near> near;
    const Model* model = nullptr;
    const std::vector<std::array<Index, 2>>* edges = nullptr;
    Scalar thickness = 0;

    Points push;                   // this sub-interval's proximity pushes, at most `thickness` each
    std::vector<Scalar> reachOf;   // each particle's move over the step

    Scalar floor() const { return kFloor * thickness; }
    // A pair's approach from per-particle moves m: the vertex's plus the farthest of the triangle's
    // corners, or the farthest end of each edge (a point of a triangle or of a segment moves at most
    // as far as its farthest corner).
    template <class F>
    Scalar approach(std::size_t k, F m) const {
        const auto& q = ids[k];
        if (pairs[k].kind == Pair::Kind::VertexTriangle) return m(0, q[0]) + std::max({m(1, q[1]), m(2, q[2]), m(3, q[3])});
        return std::max(m(0, q[0]), m(1, q[1])) + std::max(m(2, q[2]), m(3, q[3]));
    }
    // A lower bound of pair k's distance now: its last measured gap less its particles' travel since.
    Scalar gapBound(std::size_t k) const {
        return gap[k] - approach(k, [&](int j, Index i) { return travel[i] - snap[k][j]; });
    }
    void measured(std::size_t k, Scalar distance) {
        gap[k] = distance, fresh[k] = 1;
        for (int j = 0; j < 4; ++j) snap[k][j] = travel[ids[k][j]];
    }
    Scalar distanceNow(std::size_t k) const;
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
    void capsuleBounds(const Near& n);
    bool bounded(Index i, Vec3& move) const;
    bool mayMeet(Pair& p) const;
    std::array<Index, 4> particlesOf(const Pair& p) const;
    void selfBounds();
    void solidBounds();
    void separate();
    void pushApart(const Index* ids, const Scalar* weights, int n, const Vec3& normal, Scalar gap);
    void gather(contact::BroadPhase& broad, const std::vector<std::uint8_t>& pinned, const Points& xStart, const State& state,
                const RigidFrame& from, const RigidFrame& to, const std::vector<Collider>& solids,
                const ContactSettings& settings, ContactReport& report);
    bool selfPairs(contact::BroadPhase& broad, const std::vector<std::uint8_t>& pinned);
    Scalar markActive(const std::vector<std::uint8_t>& pinned);
    void advance(Scalar f, const std::vector<std::uint8_t>& pinned, ContactReport& report);
};

// Whether a self pair can come within reach during the step: a particle moves at most its straight
// move plus a push of `thickness` off it (pushes are capped), so two primitives further apart than
// their particles' moves plus three thicknesses never meet. A kept pair's distance at the start
// (p.gap) is its first measured gap.
bool ContactStage::Work::mayMeet(Pair& p) const {
    const std::array<Index, 4> q = particlesOf(p);
    auto moveOf = [&](std::initializer_list<Index> ids) {
        Scalar m = 0;
        for (Index i : ids) m = std::max(m, reachOf[i]);
        return m;
    };
    // The distance between the two primitives' boxes at the start: a lower bound of theirs, which
    // drops most pairs before the exact distance is computed.
    auto boxGap = [&](std::initializer_list<Index> a, std::initializer_list<Index> b) {
        contact::Box ba, bb;
        for (Index i : a) ba.add(y0.col(i));
        for (Index i : b) bb.add(y0.col(i));
        return (ba.lo - bb.hi).cwiseMax(bb.lo - ba.hi).cwiseMax(0).norm();
    };
    const bool vt = p.kind == Pair::Kind::VertexTriangle;
    const Scalar reach = (vt ? reachOf[q[0]] + moveOf({q[1], q[2], q[3]}) : moveOf({q[0], q[1]}) + moveOf({q[2], q[3]})) +
                         3 * thickness;
    if (vt ? boxGap({q[0]}, {q[1], q[2], q[3]}) >= reach : boxGap({q[0], q[1]}, {q[2], q[3]}) >= reach) return false;
    p.gap = vt ? contact::closestOnTriangle(y0.col(q[0]), y0.col(q[1]), y0.col(q[2]), y0.col(q[3])).distance
               : contact::closestSegments(y0.col(q[0]), y0.col(q[1]), y0.col(q[2]), y0.col(q[3])).distance;
    return p.gap < reach;
}

// A pair's particles: the vertex and the triangle's, or both edges'.
std::array<Index, 4> ContactStage::Work::particlesOf(const Pair& p) const {
    if (p.kind == Pair::Kind::VertexTriangle) {
        const Triangle& t = model->triangles()[p.b];
        return {p.a, t[0], t[1], t[2]};
    }
    const auto &e = (*edges)[p.a], &f = (*edges)[p.b];
    return {e[0], e[1], f[0], f[1]};
}

// Pair k's exact distance at the current positions.
Scalar ContactStage::Work::distanceNow(std::size_t k) const {
    const auto& q = ids[k];
    if (pairs[k].kind == Pair::Kind::VertexTriangle)
        return contact::closestOnTriangle(y.col(q[0]), y.col(q[1]), y.col(q[2]), y.col(q[3])).distance;
    return contact::closestSegments(y.col(q[0]), y.col(q[1]), y.col(q[2]), y.col(q[3])).distance;
}

ContactStage::ContactStage() : broad_(std::make_unique<contact::BroadPhase>()), work_(std::make_unique<Work>()) {}
ContactStage::~ContactStage() = default;
ContactStage::ContactStage(ContactStage&&) noexcept = default;
ContactStage& ContactStage::operator=(ContactStage&&) noexcept = default;

// Bounds from the self pairs at the current positions: every particle of a pair under kSelfShare
// of the pair's gap less the floor. A pair that separate() did not measure is measured only if the
// bound from its gap's lower bound could bind one of its particles' moves (len): if it cannot, the
// exact bound, which is larger, cannot either, and the pair changes nothing.
void ContactStage::Work::selfBounds() {
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (!fresh[k]) {
            const Scalar longest = std::max({len[ids[k][0]], len[ids[k][1]], len[ids[k][2]], len[ids[k][3]]});
            if (kSelfShare * (gapBound(k) - floor()) >= longest + kSlack) continue;
            measured(k, distanceNow(k));
        }
        const Scalar b = kSelfShare * (gap[k] - floor());
        for (Index i : ids[k]) limit(i, b);
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

// Moves the targets of n particles (weights w_k on the primitive's side, signs folded in) so that
// their weighted sum gains `gap` along `normal` (position-based: inverse masses as weights).
void ContactStage::Work::pushApart(const Index* ids, const Scalar* weights, int n, const Vec3& normal, Scalar gap) {
    Scalar denom = 0;
    for (int k = 0; k < n; ++k) denom += invMass[ids[k]] * weights[k] * weights[k];
    if (denom <= 0 || gap <= 0) return;
    const Scalar lambda = std::min(gap, thickness) / denom;
    for (int k = 0; k < n; ++k) push.col(ids[k]) += (lambda * invMass[ids[k]] * weights[k]) * normal;
}

// Proximity: self pairs and edges near a capsule that would end the sub-interval closer than
// `thickness` are pushed apart along the direction that separates them now. A self pair whose
// gap's lower bound less its approach on the way to the targets (need) clears `thickness` cannot
// end that close and is not measured; a measured pair's gap is kept for its bounds.
void ContactStage::Work::separate() {
    const auto& tris = model->triangles();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const Pair& p = pairs[k];
        if (gapBound(k) - approach(k, [&](int, Index i) { return need[i]; }) >= thickness + kSlack) continue;
        if (p.kind == Pair::Kind::VertexTriangle) {
            const Triangle& t = tris[p.b];
            const auto now = contact::closestOnTriangle(y.col(p.a), y.col(t[0]), y.col(t[1]), y.col(t[2]));
            measured(k, now.distance);
            const Vec3 w = now.weights, c = w[0] * y.col(t[0]) + w[1] * y.col(t[1]) + w[2] * y.col(t[2]);
            if (now.distance <= 0) continue;
            const Vec3 n = (y.col(p.a) - c) / now.distance;
            const Vec3 ct = w[0] * target.col(t[0]) + w[1] * target.col(t[1]) + w[2] * target.col(t[2]);
            const Index ids[4] = {p.a, t[0], t[1], t[2]};
            const Scalar ws[4] = {1, -w[0], -w[1], -w[2]};
            pushApart(ids, ws, 4, n, thickness - (target.col(p.a) - ct).dot(n));
        } else {
            const auto &e = (*edges)[p.a], &f = (*edges)[p.b];
            const auto now = contact::closestSegments(y.col(e[0]), y.col(e[1]), y.col(f[0]), y.col(f[1]));
            measured(k, now.distance);
            if (now.distance <= 0) continue;
            auto at = [&](const Points& q, const std::array<Index, 2>& s, Scalar u) { return Vec3((1 - u) * q.col(s[0]) + u * q.col(s[1])); };
            const Vec3 n = (at(y, e, now.s) - at(y, f, now.t)) / now.distance;
            const Index ids[4] = {e[0], e[1], f[0], f[1]};
            const Scalar ws[4] = {1 - now.s, now.s, -(1 - now.t), -now.t};
            pushApart(ids, ws, 4, n, thickness - (at(target, e, now.s) - at(target, f, now.t)).dot(n));
        }
    }
    for (const Near& n : near) {
        if (n.solid->shape != Collider::Shape::Capsule) continue;
        const auto [a, b] = axisOf(*n.solid);
        for (Index e : n.edges) {
            const Index i = (*edges)[e][0], j = (*edges)[e][1];
            const auto now = contact::closestSegments(y.col(i), y.col(j), a, b);
            const Vec3 p = (1 - now.s) * y.col(i) + now.s * y.col(j), q = (1 - now.t) * a + now.t * b;
            if (now.distance <= 0) continue;
            const Vec3 normal = (p - q) / now.distance;
            const Vec3 pt = (1 - now.s) * target.col(i) + now.s * target.col(j);
            const Index ids[2] = {i, j};
            const Scalar ws[2] = {1 - now.s, now.s};
            pushApart(ids, ws, 2, normal, n.solid->radius + thickness - (pt - q).dot(normal));
        }
    }
}

// The step's two ends in the carrier's frame, the self pairs and the solids' primitives that can
// come within reach (report.selfPairs, report.near).
void ContactStage::Work::gather(contact::BroadPhase& broad, const std::vector<std::uint8_t>& pinned, const Points& xStart,
                                const State& state, const RigidFrame& from, const RigidFrame& to,
                                const std::vector<Collider>& solids, const ContactSettings& settings, ContactReport& report) {
    const Index n = model->particleCount();
    const Eigen::Matrix3d r0 = from.rotation.toRotationMatrix().transpose(), r1 = to.rotation.toRotationMatrix().transpose();
    y0 = r0 * (xStart.colwise() - from.position);
    y1 = r1 * (state.x.colwise() - to.position);
    broad.refit(*model, y0, y1, 2 * settings.thickness);
    reachOf.resize(n);
    for (Index i = 0; i < n; ++i) reachOf[i] = (y1.col(i) - y0.col(i)).norm();
    edges = &broad.edges(), thickness = settings.thickness;
    near.clear();
    pushed.assign(n, 0);
    auto mayPush = [&](Index i) { pushed[i] = !pinned[i]; };
    for (const Collider& c : solids) {
        Near nr{&c, {}, {}};
        broad.near(boxOf(c, 2 * settings.thickness), pinned, nr.vertices, nr.edges);
        report.near += int(nr.vertices.size() + nr.edges.size());
        for (Index i : nr.vertices) mayPush(i);
        for (Index e : nr.edges) mayPush((*edges)[e][0]), mayPush((*edges)[e][1]);
        if (!nr.vertices.empty() || !nr.edges.empty()) near.push_back(std::move(nr));
    }
    pairs.clear(), ids.clear(), gap.clear();
    if (settings.self && !selfPairs(broad, pinned)) report.overloaded = 1;
    report.selfPairs = int(report.overloaded ? candidates : pairs.size());
}

// The self pairs, with the normal cones widened where contact may push a particle off its straight
// move: a particle in a pair or near a solid. Widening can open a flat node and give more pairs, and
// with them more particles to push: repeated until no pair adds one (each round adds at least one
// particle, so it ends). False, with no pairs, past kMaxPairsPerParticle.
bool ContactStage::Work::selfPairs(contact::BroadPhase& broad, const std::vector<std::uint8_t>& pinned) {
    const std::size_t most = kMaxPairsPerParticle * std::size_t(model->particleCount());
    const contact::Keep keep = [this](Pair& p) { return mayMeet(p); };
    for (;;) {
        broad.widen(y0, y1, pushed);
        if (const std::size_t found = broad.selfPairs(pairs, most, keep); found > most) {
            pairs.clear(), candidates = found;
            return false;
        }
        bool grew = false;
        for (const Pair& p : pairs)
            for (Index i : particlesOf(p))
                if (!pushed[i] && !pinned[i]) pushed[i] = 1, grew = true;
        if (grew) continue;
        ids.clear(), gap.clear();
        for (const Pair& p : pairs) ids.push_back(particlesOf(p)), gap.push_back(p.gap);
        snap.assign(pairs.size(), {0, 0, 0, 0});
        return true;
    }
}

// The particles the pairs and the solids' primitives involve (active), the free ones among them
// (moving) and the inverse masses; returns the longest move of a moving particle.
Scalar ContactStage::Work::markActive(const std::vector<std::uint8_t>& pinned) {
    const Index n = model->particleCount();
    active.assign(n, 0);
    auto mark = [&](Index i) { active[i] = 1; };
    auto markEdge = [&](Index e) { mark((*edges)[e][0]), mark((*edges)[e][1]); };
    for (const Pair& p : pairs) {
        if (p.kind == Pair::Kind::VertexTriangle) {
            mark(p.a);
            for (Index i : model->triangles()[p.b]) mark(i);
        } else {
            markEdge(p.a), markEdge(p.b);
        }
    }
    for (const Near& nr : near) {
        for (Index i : nr.vertices) mark(i);
        for (Index e : nr.edges) markEdge(e);
    }
    moving.clear(), touched.clear();
    Scalar reach = 0;
    invMass.assign(n, 1);
    for (Index i = 0; i < n; ++i) {
        if (pinned[i]) invMass[i] = 0;
        if (active[i] || pinned[i]) touched.push_back(i);
        if (!active[i] || pinned[i]) continue;
        moving.push_back(i);
        reach = std::max(reach, reachOf[i]);
    }
    return reach;
}

// One sub-interval, to the fraction f of the step: targets on the straight path plus the
// proximity pushes, then every active particle moved toward its target within its bound (the
// pinned ones onto theirs). Only the active and the pinned particles are touched: no pair and no
// solid reads another.
void ContactStage::Work::advance(Scalar f, const std::vector<std::uint8_t>& pinned, ContactReport& report) {
    for (Index i : touched) {
        target.col(i) = y0.col(i) + f * (y1.col(i) - y0.col(i));
        need[i] = active[i] ? (target.col(i) - y.col(i)).norm() : 0;
        push.col(i).setZero();
    }
    fresh.assign(pairs.size(), 0);
    separate();
    for (Index i : moving) {  // each particle's pushes together at most `thickness`
        const Scalar l = push.col(i).norm();
        target.col(i) += l > thickness ? Vec3(push.col(i) * (thickness / l)) : Vec3(push.col(i));
    }
    for (Index i : touched) {
        len[i] = active[i] ? (target.col(i) - y.col(i)).norm() : 0;
        bound[i] = std::numeric_limits<Scalar>::infinity();
        firstPlane[i] = -1;
    }
    planes.clear();
    selfBounds();
    solidBounds();
    for (Index i : touched) {
        if (pinned[i]) {
            travel[i] += (target.col(i) - y.col(i)).norm();
            y.col(i) = target.col(i);  // prescribed
            continue;
        }
        Vec3 move = target.col(i) - y.col(i);
        if (bounded(i, move)) ++report.limited;
        travel[i] += move.norm();
        y.col(i) += move;
    }
}

ContactReport ContactStage::apply(const Model& model, const std::vector<std::uint8_t>& pinned, const Points& xStart,
                                  State& state, const RigidFrame& from, const RigidFrame& to,
                                  const std::vector<Collider>& solids, const ContactSettings& settings, Scalar h) {
    ContactReport report;
    Work& w = *work_;
    w.model = &model;
    w.gather(*broad_, pinned, xStart, state, from, to, solids, settings, report);
    // Back in the world: each moved particle's correction becomes a change of its velocity.
    auto place = [&](Index i, const Vec3& y) {
        const Vec3 x = to.point(y);
        state.v.col(i) += (x - state.x.col(i)) / h;
        state.x.col(i) = x;
    };
    if (report.overloaded) {  // too many pairs to bound: the free particles keep their uncrossed start
        for (Index i = 0; i < model.particleCount(); ++i)
            if (!pinned[i]) place(i, w.y0.col(i));
        return report;
    }
    const Scalar reach = w.markActive(pinned);
    if (w.moving.empty()) return report;
    report.subintervals = std::clamp(int(std::ceil(reach / settings.maxMove)), 1, kMaxSubintervals);
    w.y = w.y0;
    w.target.resize(3, model.particleCount());
    w.push.resize(3, model.particleCount());
    w.bound.assign(model.particleCount(), std::numeric_limits<Scalar>::infinity());
    w.firstPlane.assign(model.particleCount(), -1);
    w.travel.assign(model.particleCount(), 0);
    w.need.resize(model.particleCount()), w.len.resize(model.particleCount());
    for (int k = 1; k <= report.subintervals; ++k) w.advance(Scalar(k) / report.subintervals, pinned, report);
    for (Index i : w.moving) place(i, w.y.col(i));
    return report;
}

}  // namespace cloth
