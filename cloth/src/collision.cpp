#include "cloth/collision.h"

#include "simd.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace cloth {

namespace {

// A sphere's centre, or the point of a capsule's segment nearest to p.
Vec3 coreNearest(const Collider& c, const Vec3& p) {
    if (c.shape != Collider::Shape::Capsule) return c.center;
    const Scalar half = std::abs(c.halfExtents.x());  // clamp needs low <= high
    return c.center + std::clamp((p - c.center).dot(c.axis), -half, half) * c.axis;
}

}  // namespace

Scalar signedDistance(const Collider& c, const Vec3& p, Vec3* normal) {
    Vec3 n = Vec3::UnitY();
    Scalar d = 0;
    switch (c.shape) {
        case Collider::Shape::Plane: {
            n = c.axis;
            d = (p - c.center).dot(n);
            break;
        }
        case Collider::Shape::Sphere:
        case Collider::Shape::Capsule: {
            const Vec3 r = p - coreNearest(c, p);
            const Scalar len = r.norm();
            // At the exact centre any direction is outward; pick one orthogonal to the axis.
            n = len > 1e-12 ? Vec3(r / len) : c.axis.unitOrthogonal();
            d = len - c.radius;
            break;
        }
        case Collider::Shape::Box: {
            const Vec3 local = c.rotation.transpose() * (p - c.center);
            const Vec3 q = local.cwiseAbs() - c.halfExtents;
            if (q.maxCoeff() > 0) {  // outside: distance to the box surface
                const Vec3 outside = q.cwiseMax(0);
                d = outside.norm();
                Vec3 ln = outside.cwiseProduct(local.cwiseSign());
                n = c.rotation * (ln / d);
            } else {  // inside: push out through the nearest face
                int axis;
                d = q.maxCoeff(&axis);
                Vec3 ln = Vec3::Zero();
                ln[axis] = local[axis] >= 0 ? 1 : -1;
                n = c.rotation * ln;
            }
            break;
        }
    }
    if (normal) *normal = n;
    return d;
}

namespace {

// The cheap reject: whether a point is certainly farther than `thickness` from the collider's
// surface, without square roots or divisions (most particles of a flag are: every one not next
// to the pole). Conservative by a relative margin far above rounding, so it never rejects a point
// that signedDistance() would put within `thickness`: it only filters, and signedDistance()
// decides every point it lets through. Prepared once per collider; the tests for one point are
// inlined into the per-particle check and the vectorized loop over a range (markNear).
struct Reject {
    Collider::Shape shape = Collider::Shape::Plane;
    bool none = true;  // rejects nothing: a plane (signedDistance is as cheap), or a negative reach
    Scalar cx = 0, cy = 0, cz = 0;
    Scalar ax = 0, ay = 0, az = 0, half = 0;  // capsule: the segment (a sphere: none)
    Mat3 R = Mat3::Identity();                // box: its axes and half sizes
    Vec3 e = Vec3::Zero();
    Scalar limit = 0;  // sphere, capsule: the squared reach; box: the largest excess along an axis
};

Reject prepareReject(const Collider& c, Scalar thickness) {
    constexpr Scalar margin = 1e-9;
    Reject r;
    r.shape = c.shape;
    r.cx = c.center.x(), r.cy = c.center.y(), r.cz = c.center.z();
    switch (c.shape) {
        case Collider::Shape::Plane: break;
        case Collider::Shape::Sphere:
        case Collider::Shape::Capsule: {
            const Scalar reach = c.radius + thickness;
            r.none = reach < 0;
            r.limit = reach * reach * (1 + margin) + margin;
            if (c.shape == Collider::Shape::Capsule) {
                r.ax = c.axis.x(), r.ay = c.axis.y(), r.az = c.axis.z();
                r.half = std::abs(c.halfExtents.x());  // clamp needs low <= high
            }
            break;
        }
        case Collider::Shape::Box:
            // Outside the box grown by `thickness` along some local axis: the distance to the box
            // is at least that axis's excess.
            r.none = false;
            r.R = c.rotation, r.e = c.halfExtents;
            r.limit = thickness + margin * (1 + std::abs(thickness) + c.halfExtents.cwiseAbs().maxCoeff());
            break;
    }
    return r;
}

// Sphere or capsule: the squared distance to the segment's nearest point within the reach.
CLOTH_INLINE inline bool nearCore(const Reject& r, Scalar x, Scalar y, Scalar z) {
    const Scalar px = x - r.cx, py = y - r.cy, pz = z - r.cz;
    const Scalar t = std::clamp(px * r.ax + py * r.ay + pz * r.az, -r.half, r.half);
    const Scalar dx = px - t * r.ax, dy = py - t * r.ay, dz = pz - t * r.az;
    return dx * dx + dy * dy + dz * dz <= r.limit;
}

CLOTH_INLINE inline bool nearBox(const Reject& r, Scalar x, Scalar y, Scalar z) {
    const Scalar px = x - r.cx, py = y - r.cy, pz = z - r.cz;
    const Scalar qx = std::abs(r.R(0, 0) * px + r.R(1, 0) * py + r.R(2, 0) * pz) - r.e.x();
    const Scalar qy = std::abs(r.R(0, 1) * px + r.R(1, 1) * py + r.R(2, 1) * pz) - r.e.y();
    const Scalar qz = std::abs(r.R(0, 2) * px + r.R(1, 2) * py + r.R(2, 2) * pz) - r.e.z();
    return std::max(qx, std::max(qy, qz)) <= r.limit;
}

bool nearPoint(const Reject& r, const Vec3& p) {
    if (r.none) return true;
    return r.shape == Collider::Shape::Box ? nearBox(r, p.x(), p.y(), p.z()) : nearCore(r, p.x(), p.y(), p.z());
}

// A point that passed the reject: moved out to `thickness` from the surface when within it, its
// velocity changed as collideParticle() says. Returns whether it moved.
bool pushOut(const Collider& c, Scalar thickness, Vec3& x, Vec3& v) {
    Vec3 n;
    const Scalar d = signedDistance(c, x, &n) - thickness;
    if (d >= 0) return false;
    x -= d * n;
    // Velocity relative to the collider: drop the inward normal part, damp the tangent.
    Vec3 rel = v - c.velocity;
    const Scalar vn = rel.dot(n);
    if (vn < 0) {
        Vec3 vt = rel - vn * n;
        const Scalar vtLen = vt.norm();
        const Scalar drop = c.friction * -vn;
        vt = vtLen > drop ? Vec3(vt * (1 - drop / vtLen)) : Vec3::Zero();
        rel = vt;
    }
    v = c.velocity + rel;
    return true;
}

}  // namespace

bool collideParticle(const Collider& c, Scalar thickness, Vec3& x, Vec3& v) {
    return nearPoint(prepareReject(c, thickness), x) && pushOut(c, thickness, x, v);
}

namespace {

// A lower bound of signedDistance(c, p) over every p in the box [lo, hi].
Scalar distanceLowerBound(const Collider& c, const Vec3& lo, const Vec3& hi) {
    const Vec3 mid = (lo + hi) / 2, half = (hi - lo) / 2;
    if (c.shape == Collider::Shape::Plane) return (mid - c.center).dot(c.axis) - half.dot(c.axis.cwiseAbs());
    // Every other shape lies within a sphere about its center.
    const Scalar reach = c.shape == Collider::Shape::Sphere    ? c.radius
                         : c.shape == Collider::Shape::Capsule ? std::abs(c.halfExtents.x()) * c.axis.norm() + c.radius
                                                               : c.halfExtents.norm();
    const Vec3 gap = ((c.center - mid).cwiseAbs() - half).cwiseMax(0);
    return gap.norm() - reach;
}

}  // namespace

namespace {

// The reject for the particles [begin, end) at once, one loop per shape with no branch per
// particle, so that it vectorizes: near[i - begin] = 0 for a particle certainly farther than
// `thickness` from the collider's surface.
CLOTH_SIMD_CLONES void markNear(const Reject& r, const Scalar* x, Index begin, Index end, std::uint8_t* near) {
    const Index count = end - begin;
    x += 3 * std::size_t(begin);
    if (r.none) {
        std::fill(near, near + count, std::uint8_t(1));
    } else if (r.shape == Collider::Shape::Box) {
        CLOTH_IVDEP
        for (Index i = 0; i < count; ++i) near[i] = nearBox(r, x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    } else {
        CLOTH_IVDEP
        for (Index i = 0; i < count; ++i) near[i] = nearCore(r, x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    }
}

// The box around the particles not flagged pinned (lo > hi with none): minima and maxima are
// exact, so the vectorized loop finds the same box as any other order.
CLOTH_SIMD_CLONES void freeBounds(const Scalar* x, const std::uint8_t* pinned, Index count, Vec3& lo, Vec3& hi) {
    constexpr Scalar inf = std::numeric_limits<Scalar>::infinity();
    Scalar lx = inf, ly = inf, lz = inf, hx = -inf, hy = -inf, hz = -inf;
    CLOTH_IVDEP
    for (Index i = 0; i < count; ++i) {
        const bool free = !pinned || !pinned[i];
        const Scalar px = x[3 * i], py = x[3 * i + 1], pz = x[3 * i + 2];
        lx = std::min(lx, free ? px : inf), ly = std::min(ly, free ? py : inf), lz = std::min(lz, free ? pz : inf);
        hx = std::max(hx, free ? px : -inf), hy = std::max(hy, free ? py : -inf), hz = std::max(hz, free ? pz : -inf);
    }
    lo = Vec3(lx, ly, lz), hi = Vec3(hx, hy, hz);
}

}  // namespace

int resolveCollisions(const std::vector<Collider>& colliders, Scalar thickness,
                      const std::vector<std::uint8_t>* pinnedFlags, State& state, ThreadPool* pool,
                      CollisionWorkspace* workspace) {
    const Index count = static_cast<Index>(state.x.cols());
    CollisionWorkspace local;
    CollisionWorkspace& ws = workspace ? *workspace : local;
    // Broad phase: a collider that cannot reach the box around the free particles is skipped for
    // every particle that no earlier collider moved (a moved particle may have left the box).
    // The margin covers the rounding of the bound, so skipping never changes a result.
    Vec3 lo, hi;
    freeBounds(state.x.data(), pinnedFlags ? pinnedFlags->data() : nullptr, count, lo, hi);
    const bool box = (lo.array() <= hi.array()).all();  // false with no free particle
    std::vector<std::uint8_t>& far = ws.far;
    far.assign(colliders.size(), 0);
    if (box) {
        const Scalar boxScale = 1 + hi.cwiseAbs().maxCoeff() + lo.cwiseAbs().maxCoeff();
        for (std::size_t c = 0; c < colliders.size(); ++c)
            far[c] = distanceLowerBound(colliders[c], lo, hi) - thickness > 1e-9 * (boxScale + colliders[c].center.norm());
    }
    std::vector<Reject> rejects;
    rejects.reserve(colliders.size());
    for (const Collider& c : colliders) rejects.push_back(prepareReject(c, thickness));
    const std::uint8_t* skip = far.data();
    const Reject* reject = rejects.data();
    ws.near.resize(count);
    ws.hit.resize(count);
    // Collider by collider over a range of particles, each particle meeting the colliders in
    // order as before (it moves only by its own collisions): first which particles the reject
    // lets through, all at once, then the rest of collideParticle() for those. A collider the
    // broad phase skips still meets the particles an earlier one moved.
    auto collide = [&](int begin, int end) {
        std::uint8_t* near = ws.near.data() + begin;  // this range's slice
        std::uint8_t* hit = ws.hit.data() + begin;
        std::fill(hit, hit + (end - begin), std::uint8_t(0));
        bool anyHit = false;
        for (std::size_t k = 0; k < colliders.size(); ++k) {
            if (skip[k] && !anyHit) continue;
            markNear(reject[k], state.x.data(), begin, end, near);
            for (Index i = begin; i < end; ++i) {
                if (!near[i - begin] || (skip[k] && !hit[i - begin]) || (pinnedFlags && (*pinnedFlags)[i])) continue;
                Vec3 x = state.x.col(i), v = state.v.col(i);
                if (!pushOut(colliders[k], thickness, x, v)) continue;
                state.x.col(i) = x;
                state.v.col(i) = v;
                hit[i - begin] = 1, anyHit = true;
            }
        }
        return int(std::count(hit, hit + (end - begin), 1));
    };
    if (!pool) return collide(0, count);
    std::atomic<int> moved{0};
    pool->run(count, [&](int begin, int end) { moved += collide(begin, end); });
    return moved;
}

}  // namespace cloth
