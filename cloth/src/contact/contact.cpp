#include "cloth/contact.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include "contact/broad_phase.h"
#include "contact/geometry.h"
#include "contact/work.h"

namespace cloth {

using namespace contact;

namespace {

// The application's loops run on several threads only for a cloth of at least this many particles.
// A pass over a 33x33 flag (1,089 particles) is a few microseconds, less than sharing it with
// another core costs: the true motion with contact on two threads took longer with its contact on
// both; at 65x65 (4,225) its broad phase took 0.6-0.85 times as long (docs/performance.md, Contact
// on two threads).
constexpr Index kParallelParticles = 2048;

// A solid's box, grown by margin.
Box boxOf(const Collider& c, Scalar margin) {
    Box b;
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

}  // namespace

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

// Pair k's closest points at the current positions (Work::Closest).
ContactStage::Work::Closest ContactStage::Work::closestNow(std::size_t k) const {
    const auto& q = ids[k];
    Closest c;
    if (pairs[k].kind == Pair::Kind::VertexTriangle) {
        const auto at = contact::closestOnTriangle(y.col(q[0]), y.col(q[1]), y.col(q[2]), y.col(q[3]));
        c.distance = at.distance, c.weights = {1, -at.weights[0], -at.weights[1], -at.weights[2]};
    } else {
        const auto at = contact::closestSegments(y.col(q[0]), y.col(q[1]), y.col(q[2]), y.col(q[3]));
        c.distance = at.distance, c.weights = {1 - at.s, at.s, -(1 - at.t), -at.t};
    }
    if (c.distance > 0) c.normal = separation(k, c, y) / c.distance;
    return c;
}

// The first primitive's closest point less the second's, with pair k's weights c, at positions `at`
// (the current ones: the pair's separation; the targets: where the sub-interval heads).
Vec3 ContactStage::Work::separation(std::size_t k, const Closest& c, const Points& at) const {
    const auto& q = ids[k];
    const auto& w = c.weights;
    if (pairs[k].kind == Pair::Kind::VertexTriangle)
        return at.col(q[0]) - Vec3(-w[1] * at.col(q[1]) + -w[2] * at.col(q[2]) + -w[3] * at.col(q[3]));
    return Vec3(w[0] * at.col(q[0]) + w[1] * at.col(q[1])) - Vec3(-w[2] * at.col(q[2]) + -w[3] * at.col(q[3]));
}

ContactStage::ContactStage() : broad_(std::make_unique<contact::BroadPhase>()), work_(std::make_unique<Work>()) {}
ContactStage::~ContactStage() = default;
ContactStage::ContactStage(ContactStage&&) noexcept = default;
ContactStage& ContactStage::operator=(ContactStage&&) noexcept = default;

// The step's two ends in the carrier's frame: y0 (the first pass's start) and y1.
void ContactStage::Work::toCarrier(const Points& xStart, const State& state, const RigidFrame& from, const RigidFrame& to) {
    const Eigen::Matrix3d r0 = from.rotation.toRotationMatrix().transpose(), r1 = to.rotation.toRotationMatrix().transpose();
    const Index n = xStart.cols();
    y0.resize(3, n), y1.resize(3, n);
    forChunks(loops, int(n), [&](int begin, int end) {
        for (Index i = begin; i < end; ++i) {
            y0.col(i) = r0 * Vec3(xStart.col(i) - from.position);
            y1.col(i) = r1 * Vec3(state.x.col(i) - to.position);
        }
    });
}

// The pass from y0 to y1: the self pairs and the solids' primitives that can come within reach
// (report.selfPairs, report.near, summed over passes).
void ContactStage::Work::gather(contact::BroadPhase& broad, const std::vector<std::uint8_t>& pinned,
                                const std::vector<Collider>& solids, const ContactSettings& settings, ContactReport& report) {
    const Index n = model->particleCount();
    contact::moveLengths(y0, y1, reachOf, loops);
    broad.refit(*model, y0, y1, 2 * settings.thickness, loops);
    edges = &broad.edges(), thickness = settings.thickness;
    halfSpaces = settings.selfBounds == ContactSettings::SelfBounds::HalfSpaces;
    near.clear();
    pushed.assign(n, 0);
    auto mayPush = [&](Index i) { pushed[i] = !pinned[i]; };
    for (const Collider& c : solids) {
        Near nr{&c, {}, {}};
        broad.near(boxOf(c, 2 * settings.thickness), pinned, nr.vertices, nr.edges);
        report.near += (long long)(nr.vertices.size() + nr.edges.size());
        for (Index i : nr.vertices) mayPush(i);
        for (Index e : nr.edges) mayPush((*edges)[e][0]), mayPush((*edges)[e][1]);
        if (!nr.vertices.empty() || !nr.edges.empty()) near.push_back(std::move(nr));
    }
    pairs.clear(), ids.clear(), gap.clear();
    bool overloaded = false;
    if (settings.self && !selfPairs(broad, pinned)) overloaded = true, report.overloaded = 1;
    report.selfPairs += (long long)(overloaded ? candidates : pairs.size());
}

// The self pairs, with the normal cones widened where contact may push a particle off its straight
// move: a particle in a pair or near a solid. Widening can open a flat node and give more pairs, and
// with them more particles to push: repeated until no pair adds one (each round adds at least one
// particle, so it ends). False, with no pairs, past kMaxPairsPerParticle.
bool ContactStage::Work::selfPairs(contact::BroadPhase& broad, const std::vector<std::uint8_t>& pinned) {
    const std::size_t most = kMaxPairsPerParticle * std::size_t(model->particleCount());
    const contact::Keep keep = [this](Pair& p) { return mayMeet(p); };
    for (;;) {
        broad.widen(y0, y1, reachOf, pushed, loops);
        if (const std::size_t found = broad.selfPairs(pairs, most, keep, loops); found > most) {
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
        normal.assign(pairs.size(), Vec3::Zero());
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

// The particles that no pair and no solid holds, on their straight moves at the fraction f of the
// pass (at its end, exactly y1).
void ContactStage::Work::straight(Scalar f) {
    for (Index i = 0; i < model->particleCount(); ++i) {
        if (active[i] || invMass[i] == 0) continue;
        y.col(i) = f == 1 ? Vec3(y1.col(i)) : Vec3(y0.col(i) + f * (y1.col(i) - y0.col(i)));
    }
}

// One pass: the pass's motion cut into sub-intervals of at most maxMove. True when a particle
// reached the edge of its region and this is not the last pass: the pass stops there, its free
// particles on their straight moves where the sub-interval ended, and the next starts from there.
// A last pass after such a stop takes the particles no pair holds to y1 (some moved in an earlier
// pass and are placed); in a step's only pass they stay where the solver put them.
bool ContactStage::Work::pass(const std::vector<std::uint8_t>& pinned, const ContactSettings& settings, bool last,
                              ContactReport& report) {
    const Index n = model->particleCount();
    const Scalar reach = markActive(pinned);
    auto done = [&] {
        if (report.passes > 0) straight(1);
        return false;
    };
    if (moving.empty()) return done();
    const int subintervals = std::clamp(int(std::ceil(reach / settings.maxMove)), 1, kMaxSubintervals);
    report.subintervals += subintervals;
    for (Index i : moving) moved[i] = 1;
    target.resize(3, n), push.resize(3, n);
    bound.assign(n, std::numeric_limits<Scalar>::infinity());
    firstPlane.assign(n, -1);
    travel.assign(n, 0);
    need.resize(n), len.resize(n);
    for (int k = 1; k <= subintervals; ++k) {
        const Scalar f = Scalar(k) / subintervals;
        if (advance(f, pinned, report) && !last) return straight(f), true;
    }
    return done();
}

// One sub-interval, to the fraction f of the pass: targets on the straight path plus the
// proximity pushes, then every active particle moved toward its target within its bound and its
// region (the pinned ones onto theirs). Only the active and the pinned particles are touched: no
// pair and no solid reads another. True if a particle was cut back to its region.
bool ContactStage::Work::advance(Scalar f, const std::vector<std::uint8_t>& pinned, ContactReport& report) {
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
    bool cut = false;
    for (Index i : touched) {
        if (pinned[i]) {
            travel[i] += (target.col(i) - y.col(i)).norm();
            y.col(i) = target.col(i);  // prescribed
            continue;
        }
        Vec3 move = target.col(i) - y.col(i);
        if (bounded(i, move)) ++report.limited;
        if (keepInRegion(i, move)) ++report.regionCuts, cut = true;
        travel[i] += move.norm();
        y.col(i) += move;
    }
    return cut;
}

ContactReport ContactStage::apply(const Model& model, const std::vector<std::uint8_t>& pinned, const Points& xStart,
                                  State& state, const RigidFrame& from, const RigidFrame& to,
                                  const std::vector<Collider>& solids, const ContactSettings& settings, Scalar h,
                                  ParallelFor* loops) {
    ContactReport report;
    report.applications = 1;
    Work& w = *work_;
    w.model = &model, w.loops = model.particleCount() >= kParallelParticles ? loops : nullptr;
    w.toCarrier(xStart, state, from, to);
    w.y = w.y0;
    w.moved.assign(model.particleCount(), 0);
    // Back in the world: each moved particle's correction becomes a change of its velocity.
    auto place = [&](Index i, const Vec3& y) {
        const Vec3 x = to.point(y);
        state.v.col(i) += (x - state.x.col(i)) / h;
        state.x.col(i) = x;
    };
    for (int pass = 0;; ++pass) {
        const auto t0 = std::chrono::steady_clock::now();
        w.gather(*broad_, pinned, solids, settings, report);
        report.broadPhaseMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (report.overloaded) {  // too many pairs to bound: the free particles keep the pass's uncrossed start
            for (Index i = 0; i < model.particleCount(); ++i)
                if (!pinned[i]) place(i, w.y0.col(i));
            return report;
        }
        if (!w.pass(pinned, settings, pass == kMaxRestarts, report)) break;
        ++report.passes;
        w.y0 = w.y;
    }
    for (Index i = 0; i < model.particleCount(); ++i)
        if (w.moved[i]) place(i, w.y.col(i));
    return report;
}

}  // namespace cloth
