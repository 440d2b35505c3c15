#pragma once
// The colliders at every substep of the small_steps solver: a float test per particle rejects
// those certainly clear of every collider (most of a flag); the rest meet each collider through
// collideParticle (collision.h) in double, in world coordinates, exactly as resolveCollisions
// treats them.

#include <cstdint>
#include <vector>

#include "cloth/collision.h"
#include "small_steps/stencil_cloth.h"

namespace cloth {

class SubstepColliders {
public:
    // The colliders of one step, relative to `origin` (the stencil state's), each particle within
    // `thickness` of one met; `skip[i] != 0` leaves particle i alone (null: none).
    void prepare(const std::vector<Collider>* colliders, Scalar thickness, const std::vector<std::uint8_t>* skip,
                 const Vec3& origin);
    bool any() const { return !colliders_.empty(); }
    // Resolves the particles of [begin, end) of state `s`.
    void resolve(StencilState& s, int begin, int end) const;

private:
    struct Near {  // the float reject of one collider, relative to the origin
        Collider::Shape shape;
        float cx, cy, cz, ax, ay, az, half, reach2;  // sphere, capsule: centre, axis, half length, reach^2
        float r[9], ex, ey, ez, reach;                // box: axes (columns), half sizes, reach
    };
    bool near(const Near& n, float x, float y, float z) const;
    std::vector<Collider> colliders_;
    std::vector<Near> near_;
    Scalar thickness_ = 0;
    const std::vector<std::uint8_t>* skip_ = nullptr;
    Vec3 origin_ = Vec3::Zero();
};

}  // namespace cloth
