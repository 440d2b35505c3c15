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

// True when p is certainly farther than `thickness` from the collider's surface: a cheap test
// without square roots or divisions that most particles of a flag pass (every one not next to
// the pole). Conservative by a relative margin far above rounding, so it never skips a particle
// that signedDistance() would put within `thickness`.
bool clearOf(const Collider& c, Scalar thickness, const Vec3& p) {
    constexpr Scalar margin = 1e-9;
    switch (c.shape) {
        case Collider::Shape::Plane: return false;  // signedDistance is as cheap
        case Collider::Shape::Sphere:
        case Collider::Shape::Capsule: {
            const Scalar reach = c.radius + thickness;
            return reach >= 0 && (p - coreNearest(c, p)).squaredNorm() > reach * reach * (1 + margin) + margin;
        }
        case Collider::Shape::Box: {
            // Outside the box grown by `thickness` along some local axis: the distance to the
            // box is at least that axis's excess.
            const Vec3 q = (c.rotation.transpose() * (p - c.center)).cwiseAbs() - c.halfExtents;
            return q.maxCoeff() > thickness + margin * (1 + std::abs(thickness) + c.halfExtents.cwiseAbs().maxCoeff());
        }
    }
    return false;
}

}  // namespace

bool collideParticle(const Collider& c, Scalar thickness, Vec3& x, Vec3& v) {
    if (clearOf(c, thickness, x)) return false;
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

// clearOf() for the particles [begin, end) at once, without a branch per particle, so that the
// loop vectorizes: near[i - begin] = 0 for a particle certainly farther than `thickness` from the
// collider's surface. It is only a filter, conservative by the same margin as clearOf(), and
// collideParticle() decides every particle it lets through, so its rounding changes no result.
CLOTH_SIMD_CLONES void markNear(const Collider& c, Scalar thickness, const Scalar* x, Index begin, Index end,
                                std::uint8_t* near) {
    constexpr Scalar margin = 1e-9;
    const Scalar cx = c.center.x(), cy = c.center.y(), cz = c.center.z();
    const Index count = end - begin;
    x += 3 * std::size_t(begin);
    switch (c.shape) {
        case Collider::Shape::Sphere:
        case Collider::Shape::Capsule: {
            const Scalar reach = c.radius + thickness;
            if (reach < 0) break;
            const Scalar limit = reach * reach * (1 + margin) + margin;
            const Scalar half = c.shape == Collider::Shape::Capsule ? std::abs(c.halfExtents.x()) : 0;
            const Scalar ax = c.axis.x(), ay = c.axis.y(), az = c.axis.z();
            CLOTH_IVDEP
            for (Index i = 0; i < count; ++i) {
                const Scalar px = x[3 * i] - cx, py = x[3 * i + 1] - cy, pz = x[3 * i + 2] - cz;
                const Scalar t = std::clamp(px * ax + py * ay + pz * az, -half, half);
                const Scalar dx = px - t * ax, dy = py - t * ay, dz = pz - t * az;
                near[i] = dx * dx + dy * dy + dz * dz <= limit;
            }
            return;
        }
        case Collider::Shape::Box: {
            const Scalar limit = thickness + margin * (1 + std::abs(thickness) + c.halfExtents.cwiseAbs().maxCoeff());
            const Mat3& R = c.rotation;
            const Vec3& e = c.halfExtents;
            CLOTH_IVDEP
            for (Index i = 0; i < count; ++i) {
                const Scalar px = x[3 * i] - cx, py = x[3 * i + 1] - cy, pz = x[3 * i + 2] - cz;
                const Scalar qx = std::abs(R(0, 0) * px + R(1, 0) * py + R(2, 0) * pz) - e.x();
                const Scalar qy = std::abs(R(0, 1) * px + R(1, 1) * py + R(2, 1) * pz) - e.y();
                const Scalar qz = std::abs(R(0, 2) * px + R(1, 2) * py + R(2, 2) * pz) - e.z();
                near[i] = std::max(qx, std::max(qy, qz)) <= limit;
            }
            return;
        }
        case Collider::Shape::Plane: break;  // signedDistance is as cheap
    }
    std::fill(near, near + count, std::uint8_t(1));
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
                      const std::vector<std::uint8_t>* pinnedFlags, State& state, ThreadPool* pool) {
    const Index count = static_cast<Index>(state.x.cols());
    // Broad phase: a collider that cannot reach the box around the free particles is skipped for
    // every particle that no earlier collider moved (a moved particle may have left the box).
    // The margin covers the rounding of the bound, so skipping never changes a result.
    Vec3 lo, hi;
    freeBounds(state.x.data(), pinnedFlags ? pinnedFlags->data() : nullptr, count, lo, hi);
    const bool box = (lo.array() <= hi.array()).all();  // false with no free particle
    static thread_local std::vector<std::uint8_t> far;
    far.assign(colliders.size(), 0);
    if (box) {
        const Scalar boxScale = 1 + hi.cwiseAbs().maxCoeff() + lo.cwiseAbs().maxCoeff();
        for (std::size_t c = 0; c < colliders.size(); ++c)
            far[c] = distanceLowerBound(colliders[c], lo, hi) - thickness > 1e-9 * (boxScale + colliders[c].center.norm());
    }
    const std::uint8_t* skip = far.data();
    // Collider by collider over a range of particles, each particle meeting the colliders in
    // order as before (it moves only by its own collisions): first which particles are near the
    // collider, all at once, then collideParticle() for those. A collider the broad phase skips
    // still meets the particles an earlier one moved.
    auto collide = [&](int begin, int end) {
        static thread_local std::vector<std::uint8_t> near, hit;  // this thread's scratch
        near.resize(end - begin);
        hit.assign(end - begin, 0);
        bool anyHit = false;
        for (std::size_t k = 0; k < colliders.size(); ++k) {
            if (skip[k] && !anyHit) continue;
            markNear(colliders[k], thickness, state.x.data(), begin, end, near.data());
            for (Index i = begin; i < end; ++i) {
                if (!near[i - begin] || (skip[k] && !hit[i - begin]) || (pinnedFlags && (*pinnedFlags)[i])) continue;
                Vec3 x = state.x.col(i), v = state.v.col(i);
                if (!collideParticle(colliders[k], thickness, x, v)) continue;
                state.x.col(i) = x;
                state.v.col(i) = v;
                hit[i - begin] = 1, anyHit = true;
            }
        }
        return int(std::count(hit.begin(), hit.end(), 1));
    };
    if (!pool) return collide(0, count);
    std::atomic<int> moved{0};
    pool->run(count, [&](int begin, int end) { moved += collide(begin, end); });
    return moved;
}

}  // namespace cloth
