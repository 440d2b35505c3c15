#include "cloth/collision.h"

#include <algorithm>
#include <cmath>

namespace cloth {

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
            Vec3 closest = c.center;
            if (c.shape == Collider::Shape::Capsule) {
                const Scalar half = std::abs(c.halfExtents.x());  // clamp needs low <= high
                const Scalar t = std::clamp((p - c.center).dot(c.axis), -half, half);
                closest = c.center + t * c.axis;
            }
            const Vec3 r = p - closest;
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

int resolveCollisions(const std::vector<Collider>& colliders, Scalar thickness,
                      const std::vector<std::uint8_t>* pinnedFlags, State& state) {
    int moved = 0;
    for (Index i = 0; i < static_cast<Index>(state.x.cols()); ++i) {
        if (pinnedFlags && (*pinnedFlags)[i]) continue;
        bool hit = false;
        for (const Collider& c : colliders) {
            Vec3 n;
            const Scalar d = signedDistance(c, state.x.col(i), &n) - thickness;
            if (d >= 0) continue;
            state.x.col(i) -= d * n;
            // Velocity relative to the collider: drop the inward normal part, damp the tangent.
            Vec3 rel = state.v.col(i) - c.velocity;
            const Scalar vn = rel.dot(n);
            if (vn < 0) {
                Vec3 vt = rel - vn * n;
                const Scalar vtLen = vt.norm();
                const Scalar drop = c.friction * -vn;
                vt = vtLen > drop ? Vec3(vt * (1 - drop / vtLen)) : Vec3::Zero();
                rel = vt;
            }
            state.v.col(i) = c.velocity + rel;
            hit = true;
        }
        moved += hit;
    }
    return moved;
}

}  // namespace cloth
