#include "small_steps/collisions.h"

#include <algorithm>
#include <cmath>

#include "simd.h"

namespace cloth {

namespace {

// Far above float's rounding of positions a few metres from the origin: the reject only ever
// lets more particles through to collideParticle, which decides.
constexpr float kMargin = 1e-3f;

struct MaskArgs {
    const float *x, *y, *z;
    float* near;  // set to 1 where a particle may be within reach
};

// Capsule or sphere (half = 0): within reach of the segment.
CLOTH_SIMD_CLONES void markCore(const MaskArgs& m, float cx, float cy, float cz, float ax, float ay, float az,
                                float half, float reach2, int begin, int end) {
    const float *__restrict x = m.x, *__restrict y = m.y, *__restrict z = m.z;
    float* __restrict near = m.near;
CLOTH_IVDEP
    for (int p = begin; p < end; ++p) {
        const float px = x[p] - cx, py = y[p] - cy, pz = z[p] - cz;
        const float t = std::clamp(px * ax + py * ay + pz * az, -half, half);
        const float dx = px - t * ax, dy = py - t * ay, dz = pz - t * az;
        near[p] = dx * dx + dy * dy + dz * dz <= reach2 ? 1.0f : near[p];
    }
}

// Plane (normal a): on the inner side of the plane moved out by the reach.
CLOTH_SIMD_CLONES void markPlane(const MaskArgs& m, float cx, float cy, float cz, float ax, float ay, float az,
                                 float reach, int begin, int end) {
    const float *__restrict x = m.x, *__restrict y = m.y, *__restrict z = m.z;
    float* __restrict near = m.near;
CLOTH_IVDEP
    for (int p = begin; p < end; ++p)
        near[p] = (x[p] - cx) * ax + (y[p] - cy) * ay + (z[p] - cz) * az <= reach ? 1.0f : near[p];
}

// Box (axes r, columns; half sizes e): inside the box grown by the reach along every axis.
CLOTH_SIMD_CLONES void markBox(const MaskArgs& m, float cx, float cy, float cz, const float* r, float ex, float ey,
                               float ez, float reach, int begin, int end) {
    const float *__restrict x = m.x, *__restrict y = m.y, *__restrict z = m.z;
    float* __restrict near = m.near;
    const float r0 = r[0], r1 = r[1], r2 = r[2], r3 = r[3], r4 = r[4], r5 = r[5], r6 = r[6], r7 = r[7], r8 = r[8];
CLOTH_IVDEP
    for (int p = begin; p < end; ++p) {
        const float px = x[p] - cx, py = y[p] - cy, pz = z[p] - cz;
        const float qx = std::abs(r0 * px + r1 * py + r2 * pz) - ex, qy = std::abs(r3 * px + r4 * py + r5 * pz) - ey,
                    qz = std::abs(r6 * px + r7 * py + r8 * pz) - ez;
        near[p] = qx <= reach && qy <= reach && qz <= reach ? 1.0f : near[p];
    }
}

}  // namespace

void SubstepColliders::prepare(const std::vector<Collider>* colliders, Scalar thickness,
                               const std::vector<std::uint8_t>* skip, const Vec3& origin) {
    colliders_ = colliders ? *colliders : std::vector<Collider>{};
    thickness_ = thickness, skip_ = skip, origin_ = origin;
    near_.clear();
    for (const Collider& c : colliders_) {
        Near n{};
        n.shape = c.shape;
        const Vec3 center = c.center - origin;
        n.cx = float(center.x()), n.cy = float(center.y()), n.cz = float(center.z());
        n.ax = float(c.axis.x()), n.ay = float(c.axis.y()), n.az = float(c.axis.z());
        n.half = c.shape == Collider::Shape::Capsule ? float(std::abs(c.halfExtents.x())) : 0.0f;
        const float reach = float(c.radius + thickness) + kMargin;
        n.reach2 = reach * reach;
        n.reach = float(thickness) + kMargin;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) n.r[3 * i + j] = float(c.rotation(j, i));  // row i: axis i
        n.ex = float(c.halfExtents.x()), n.ey = float(c.halfExtents.y()), n.ez = float(c.halfExtents.z());
        near_.push_back(n);
    }
}

void SubstepColliders::resolve(StencilState& s, int begin, int end) const {
    float* near = s.scratch.at();
    std::fill(near + begin, near + end, 0.0f);
    const MaskArgs m{s.x.x.at(), s.x.y.at(), s.x.z.at(), near};
    for (const Near& n : near_) switch (n.shape) {
            case Collider::Shape::Plane: markPlane(m, n.cx, n.cy, n.cz, n.ax, n.ay, n.az, n.reach, begin, end); break;
            case Collider::Shape::Sphere:
            case Collider::Shape::Capsule:
                markCore(m, n.cx, n.cy, n.cz, n.ax, n.ay, n.az, n.half, n.reach2, begin, end);
                break;
            case Collider::Shape::Box: markBox(m, n.cx, n.cy, n.cz, n.r, n.ex, n.ey, n.ez, n.reach, begin, end); break;
        }
    float *x = s.x.x.at(), *y = s.x.y.at(), *z = s.x.z.at(), *vx = s.v.x.at(), *vy = s.v.y.at(), *vz = s.v.z.at();
    for (int p = begin; p < end; ++p) {
        if (near[p] == 0.0f || (skip_ && (*skip_)[std::size_t(p)])) continue;
        Vec3 xw = origin_ + Vec3(x[p], y[p], z[p]), vw(vx[p], vy[p], vz[p]);
        bool moved = false;
        for (const Collider& c : colliders_) moved = collideParticle(c, thickness_, xw, vw) || moved;
        if (!moved) continue;
        const Vec3 rel = xw - origin_;
        x[p] = float(rel.x()), y[p] = float(rel.y()), z[p] = float(rel.z());
        vx[p] = float(vw.x()), vy[p] = float(vw.y()), vz[p] = float(vw.z());
    }
}

}  // namespace cloth
