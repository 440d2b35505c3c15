#pragma once
// Simple colliders the cloth is kept out of: planes, spheres, capsules and oriented boxes, each
// with a thickness. Resolved after a step by projecting penetrating particles to the surface and,
// when they move into the collider, removing that inward normal velocity (relative to the
// collider) and reducing the tangential part by friction times the removed normal speed
// (Coulomb-like; never reversed). A particle already moving out keeps its velocity.

#include <vector>

#include "cloth/model.h"
#include "cloth/thread_pool.h"

namespace cloth {

struct Collider {
    enum class Shape { Plane, Sphere, Capsule, Box } shape = Shape::Plane;
    Vec3 center = Vec3::Zero();   // plane: a point on it; capsule: segment midpoint
    Vec3 axis = Vec3::UnitY();    // plane: normal; capsule: unit segment direction
    Mat3 rotation = Mat3::Identity();  // box: columns are its local axes in world
    Vec3 halfExtents = Vec3::Zero();   // box: half sizes; capsule: |x| = half segment length
    Scalar radius = 0;            // sphere/capsule radius
    Vec3 velocity = Vec3::Zero(); // collider's velocity (for relative friction)
    Scalar friction = 0.3;
};

// One particle against one collider: if it lies within `thickness` of the surface, it moves to
// that distance along the surface normal, its inward velocity relative to the collider is
// dropped and its tangential velocity damped by Coulomb friction. Returns whether it moved.
bool collideParticle(const Collider& c, Scalar thickness, Vec3& x, Vec3& v);

// collideParticle for every particle and collider, each particle meeting the colliders in order.
// Pinned particles (flags[i] != 0) are left alone. Returns the number of particles moved (a
// particle inside two colliders counts once). A collider that cannot reach the bounding box of
// the free particles is skipped (same results, tested against the loop over every pair). The
// particles are split among `pool`'s threads when given (each particle on its own: the same bits).
// `workspace`: scratch reused from call to call, owned by the caller (null: a fresh one).
struct CollisionWorkspace {
    std::vector<std::uint8_t> far, near, hit;  // per collider; per particle (each range its own slice)
};
int resolveCollisions(const std::vector<Collider>& colliders, Scalar thickness,
                      const std::vector<std::uint8_t>* pinnedFlags, State& state, ThreadPool* pool = nullptr,
                      CollisionWorkspace* workspace = nullptr);

// Signed distance from p to the collider's surface (negative inside).
Scalar signedDistance(const Collider& c, const Vec3& p, Vec3* normal);

}  // namespace cloth
