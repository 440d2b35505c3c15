// Collisions (cloth/collision.h): distances and normals of planes, capsules and boxes from their
// geometry, written here; projection onto the surface and Coulomb friction written out.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "physics_support.h"
#include <Eigen/Geometry>

#include "cloth/collision.h"

using namespace cloth;
using namespace cloth::test;

namespace {

// ---------------------------------------------------------------------------------------------
// Collisions: each shape's distance and outward normal from its geometric definition.

struct Surface {
    Scalar distance;  // signed, negative inside
    Vec3 normal;      // outward unit normal of the nearest surface point
};

Surface planeSurface(const Vec3& point, const Vec3& unitNormal, const Vec3& p) {
    return {(p - point).dot(unitNormal), unitNormal};
}

// Capsule between segment ends a and b: distance to the segment minus the radius.
Surface capsuleSurface(const Vec3& a, const Vec3& b, Scalar radius, const Vec3& p) {
    const Vec3 ab = b - a;
    const Scalar t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), Scalar(0), Scalar(1));
    const Vec3 r = p - (a + t * ab);
    return {r.norm() - radius, r.normalized()};
}

// Oriented box: outside, the distance to the closest point of the solid box; inside, minus the
// distance to the nearest face.
Surface boxSurface(const Vec3& center, const Mat3& rotation, const Vec3& half, const Vec3& p) {
    const Vec3 local = rotation.transpose() * (p - center);
    const Vec3 closest = local.cwiseMax(-half).cwiseMin(half);
    if (closest != local) {
        const Vec3 away = local - closest;
        return {away.norm(), rotation * away.normalized()};
    }
    int face = 0;
    for (int a = 1; a < 3; ++a)
        if (half[a] - std::abs(local[a]) < half[face] - std::abs(local[face])) face = a;
    Vec3 n = Vec3::Zero();
    n[face] = local[face] >= 0 ? 1 : -1;
    return {-(half[face] - std::abs(local[face])), rotation * n};
}

struct CollisionShape {
    const char* name;
    Collider collider;
    Surface (*surface)(const Collider&, const Vec3&);  // this file's geometry, not signedDistance
    Vec3 inside;                                       // a point well inside the shape
};

std::vector<CollisionShape> collisionShapes() {
    std::vector<CollisionShape> shapes;
    {
        Collider c;
        c.shape = Collider::Shape::Plane;
        c.center = Vec3(0.3, -0.5, 0.2);
        c.axis = Vec3(0.2, 1, -0.1).normalized();
        c.velocity = Vec3(0.4, 0, -0.2);
        c.friction = 0.4;
        shapes.push_back({"plane", c,
                          [](const Collider& c, const Vec3& p) { return planeSurface(c.center, c.axis, p); },
                          c.center - 0.07 * c.axis + Vec3(0.1, 0, 0.3)});
    }
    {
        Collider c;
        c.shape = Collider::Shape::Capsule;
        c.center = Vec3(0.1, 0.2, -0.3);
        c.axis = Vec3(1, 0.5, 0.2).normalized();
        c.halfExtents = Vec3(0.6, 0, 0);
        c.radius = 0.25;
        c.velocity = Vec3(0, -0.5, 0.3);
        c.friction = 0.3;
        shapes.push_back({"capsule", c,
                          [](const Collider& c, const Vec3& p) {
                              const Vec3 end = c.halfExtents.x() * c.axis;
                              return capsuleSurface(c.center - end, c.center + end, c.radius, p);
                          },
                          c.center + 0.3 * c.axis + 0.12 * c.axis.unitOrthogonal()});
    }
    {
        Collider c;
        c.shape = Collider::Shape::Box;
        c.center = Vec3(-0.2, 0.4, 0.1);
        c.rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
        c.halfExtents = Vec3(0.5, 0.3, 0.4);
        c.velocity = Vec3(0.2, 0.1, 0);
        c.friction = 0.5;
        shapes.push_back({"box", c,
                          [](const Collider& c, const Vec3& p) {
                              return boxSurface(c.center, c.rotation, c.halfExtents, p);
                          },
                          // nearest face: local +y, 0.05 inside it
                          c.center + c.rotation * Vec3(0.1, 0.25, -0.1)});
    }
    return shapes;
}

// What collision.h documents for a particle pushed out along the outward normal n: the normal
// part of its velocity relative to the collider is removed if it points inward, and the
// tangential part loses (Coulomb) friction * |removed normal speed|, never reversing.
Vec3 documentedVelocityAfterContact(const Vec3& v, const Collider& c, const Vec3& n) {
    const Vec3 rel = v - c.velocity;
    const Scalar vn = rel.dot(n);
    if (vn >= 0) return v;  // separating: untouched
    const Vec3 tangential = rel - vn * n;
    const Scalar speed = tangential.norm(), loss = c.friction * -vn;
    return c.velocity + (speed > loss ? Vec3((speed - loss) / speed * tangential) : Vec3::Zero());
}

}  // namespace

// =============================================================================================
// 2. Collisions

TEST(PhysicsCollision, PenetratingParticlesEndOnTheSurfaceWithoutInwardVelocity) {
    const Scalar thickness = 0.01;
    for (const CollisionShape& shape : collisionShapes()) {
        const Collider& c = shape.collider;
        const Surface at = shape.surface(c, shape.inside);
        ASSERT_LT(at.distance, -0.02) << shape.name << ": test point not inside";
        const Vec3 n = at.normal, t = at.normal.unitOrthogonal();
        // Particles 0-3 inside: sliding (tangential speed above friction * normal speed),
        // sticking (below it), separating (moving out), pinned. Particle 4 outside.
        const Vec3 velocities[] = {c.velocity - 2 * n + 3 * t, c.velocity - 2 * n + 0.1 * t,
                                   c.velocity + 1 * n + 0.5 * t, c.velocity - 2 * n, -n};
        State state;
        state.x.resize(3, 5);
        state.v.resize(3, 5);
        for (int i = 0; i < 5; ++i) {
            state.x.col(i) = i < 4 ? shape.inside : Vec3(shape.inside + (0.1 - at.distance) * n);
            state.v.col(i) = velocities[i];
        }
        const std::vector<std::uint8_t> pinned = {0, 0, 0, 1, 0};
        const State before = state;
        EXPECT_EQ(resolveCollisions({c}, thickness, &pinned, state), 3) << shape.name;

        for (int i = 0; i < 3; ++i) {
            const Vec3 x = state.x.col(i), v = state.v.col(i);
            const Surface after = shape.surface(c, x);
            EXPECT_NEAR(after.distance, thickness, 1e-12) << shape.name << " particle " << i << " not on the surface";
            EXPECT_LE((x - before.x.col(i)).cross(n).norm(), 1e-12)
                << shape.name << " particle " << i << " not moved along the normal";
            EXPECT_GE((v - c.velocity).dot(after.normal), -1e-12)
                << shape.name << " particle " << i << " still moves into the collider";
            const Vec3 expected = documentedVelocityAfterContact(before.v.col(i), c, n);
            EXPECT_LE((v - expected).norm(), 1e-12)
                << shape.name << " particle " << i << ": velocity " << v.transpose() << ", expected "
                << expected.transpose();
        }
        for (int i : {3, 4}) {  // pinned, and outside
            EXPECT_EQ(state.x.col(i), before.x.col(i)) << shape.name << " particle " << i;
            EXPECT_EQ(state.v.col(i), before.v.col(i)) << shape.name << " particle " << i;
        }
    }
}

TEST(PhysicsCollision, SignedDistanceAndNormalMatchTheShapeGeometry) {
    for (const CollisionShape& shape : collisionShapes()) {
        std::mt19937 rng(11);
        int inside = 0, outside = 0, wrong = 0;
        std::string firstWrong;
        for (int k = 0; k < 400; ++k) {
            const Vec3 p = shape.collider.center + randomVec(rng, -1.2, 1.2);
            const Surface expected = shape.surface(shape.collider, p);
            Vec3 normal;
            const Scalar d = signedDistance(shape.collider, p, &normal);
            (expected.distance < 0 ? inside : outside) += 1;
            if (std::abs(d - expected.distance) <= 1e-12 && (normal - expected.normal).norm() <= 1e-9) continue;
            if (wrong++ == 0) {
                std::ostringstream s;
                s << "at " << p.transpose() << ": distance " << d << ", normal " << normal.transpose()
                  << "; expected " << expected.distance << ", " << expected.normal.transpose();
                firstWrong = s.str();
            }
        }
        EXPECT_EQ(wrong, 0) << shape.name << ": signedDistance differs from the geometry at " << wrong
                            << " of 400 points, first " << firstWrong;
        EXPECT_GT(inside, 10) << shape.name;  // both sides really sampled
        EXPECT_GT(outside, 10) << shape.name;
    }
}

TEST(PhysicsCollision, ExactlyTheParticlesWithinTheThicknessOfTheGeometryMove) {
    // collideParticle rejects most particles with a cheap test before the signed distance; it
    // must move every particle closer than `thickness` to the surface (this file's geometry) and
    // no other, also just inside and just outside that shell. So must resolveCollisions, which
    // rejects a whole range of particles at once with its own vectorized test.
    const Scalar thickness = 0.05;
    for (const CollisionShape& shape : collisionShapes()) {
        std::mt19937 rng(5);
        int moved = 0, kept = 0, wrong = 0;
        std::string firstWrong;
        State cloud;
        cloud.x = Points(3, 2000);
        cloud.v = Vec3(0.3, -1, 0.2).replicate(1, 2000);
        std::vector<bool> within(2000);
        for (int k = 0; k < 2000; ++k) {
            Vec3 p = shape.collider.center + randomVec(rng, -1.5, 1.5);
            if (k % 2) {  // onto the shell at `thickness`, then 1e-7 in or out
                const Surface at = shape.surface(shape.collider, p);
                p += (thickness - at.distance + (k % 4 == 1 ? -1e-7 : 1e-7)) * at.normal;
            }
            const Scalar distance = shape.surface(shape.collider, p).distance;
            cloud.x.col(k) = p;
            within[k] = distance < thickness;
            Vec3 x = p, v = Vec3(0.3, -1, 0.2);
            const bool hit = collideParticle(shape.collider, thickness, x, v);
            (hit ? moved : kept) += 1;
            if (hit == (distance < thickness) && (hit || (x == p && v == Vec3(0.3, -1, 0.2)))) continue;
            if (wrong++ == 0) {
                std::ostringstream s;
                s << "at " << p.transpose() << " (distance " << distance << "): moved " << hit;
                firstWrong = s.str();
            }
        }
        EXPECT_EQ(wrong, 0) << shape.name << ": " << wrong << " of 2000 particles wrong, first " << firstWrong;
        EXPECT_GT(moved, 100) << shape.name;
        EXPECT_GT(kept, 100) << shape.name;

        const Points before = cloud.x;
        EXPECT_EQ(resolveCollisions({shape.collider}, thickness, nullptr, cloud), moved) << shape.name;
        int wrongInCloud = 0;
        for (int k = 0; k < 2000; ++k) wrongInCloud += (cloud.x.col(k) != before.col(k)) != within[k];
        EXPECT_EQ(wrongInCloud, 0) << shape.name << ": resolveCollisions moved the wrong particles";
    }
}


TEST(PhysicsCollision, AParticleInTwoCollidersCountsOnceAndACapsuleMayBeGivenReversed) {
    // The count is of particles (collision.h), not of particle-collider hits: before, a particle
    // inside two overlapping planes counted twice.
    Collider floor, wall;
    floor.axis = Vec3::UnitY();
    wall.axis = Vec3::UnitX();
    State state;
    state.x = Points::Zero(3, 2);
    state.x.col(0) = Vec3(-0.1, -0.1, 0);  // under the floor and behind the wall
    state.x.col(1) = Vec3(1, 1, 0);        // outside both
    state.v = Points::Zero(3, 2);
    EXPECT_EQ(resolveCollisions({floor, wall}, 0, nullptr, state), 1);
    EXPECT_GE(state.x(0, 0), -1e-12);
    EXPECT_GE(state.x(1, 0), -1e-12);
    // A negative half length was undefined behaviour (std::clamp with low > high); it now means
    // the same segment as its absolute value: distance from (0, 2, 0) to the segment x in [-1, 1].
    Collider capsule;
    capsule.shape = Collider::Shape::Capsule;
    capsule.axis = Vec3::UnitX();
    capsule.radius = 0.5;
    capsule.halfExtents = Vec3(-1, 0, 0);
    EXPECT_NEAR(signedDistance(capsule, Vec3(0.7, 2, 0), nullptr), 1.5, 1e-12);
    EXPECT_NEAR(signedDistance(capsule, Vec3(3, 0, 0), nullptr), 1.5, 1e-12);
}

TEST(PhysicsCollision, SkippingCollidersFarFromTheClothChangesNothing) {
    // resolveCollisions skips colliders that cannot reach the box around the free particles.
    // Reference: collideParticle for every particle and every collider in order. The colliders:
    // a ball in the middle of the cloud (reaches it), a ground plane, a box and a capsule well
    // away (skipped), and a plane just above the cloud (skipped by the box test), into which the
    // ball pushes some particles: those must still meet it, as in the reference.
    std::mt19937 rng(11);
    State state;
    state.x = Points::Zero(3, 400);
    state.v = Points::Zero(3, 400);
    for (Index i = 0; i < 400; ++i) {
        state.x.col(i) = randomVec(rng, 0, 1);
        state.v.col(i) = randomVec(rng, -1, 1);
    }
    std::vector<std::uint8_t> pinned(400, 0);
    pinned[7] = pinned[100] = 1;
    std::vector<Collider> colliders(5);
    colliders[0].shape = Collider::Shape::Sphere;
    colliders[0].center = Vec3(0.5, 0.5, 0.5);
    colliders[0].radius = 0.6;
    colliders[0].velocity = Vec3(0.2, 0, 0);
    colliders[1].center = Vec3(0, -2, 0);  // the ground plane, far below
    colliders[2].shape = Collider::Shape::Box;
    colliders[2].center = Vec3(3, 0.5, 0.5);
    colliders[2].halfExtents = Vec3(0.5, 1, 1);
    colliders[2].rotation = Eigen::AngleAxisd(0.3, Vec3::UnitY()).toRotationMatrix();
    colliders[3].shape = Collider::Shape::Capsule;
    colliders[3].center = Vec3(0.5, 0.5, -2);
    colliders[3].axis = Vec3::UnitX();
    colliders[3].halfExtents = Vec3(1, 0, 0);
    colliders[3].radius = 0.2;
    colliders[4].center = Vec3(0, 0, 1.04);  // a plane facing down, 4 cm above the cloud
    colliders[4].axis = -Vec3::UnitZ();
    const Scalar thickness = 0.01;

    State reference = state;
    int movedReference = 0;
    for (Index i = 0; i < 400; ++i) {
        if (pinned[i]) continue;
        bool hit = false;
        for (const Collider& c : colliders) {
            Vec3 x = reference.x.col(i), v = reference.v.col(i);
            if (collideParticle(c, thickness, x, v)) {
                reference.x.col(i) = x;
                reference.v.col(i) = v;
                hit = true;
            }
        }
        movedReference += hit;
    }
    ASSERT_GT(movedReference, 50);
    int pushedIntoTheTopPlane = 0;
    for (Index i = 0; i < 400; ++i) pushedIntoTheTopPlane += state.x(2, i) <= 1 &&
                                                             reference.x(2, i) >= 1.04 - thickness - 1e-12 &&
                                                             reference.x(2, i) <= 1.04 - thickness + 1e-12;
    ASSERT_GT(pushedIntoTheTopPlane, 0) << "the ball should push some particles up against the top plane";

    // Alone, and with the particles split between two threads.
    ThreadPool two(2);
    State split = state;
    EXPECT_EQ(resolveCollisions(colliders, thickness, &pinned, state), movedReference);
    EXPECT_TRUE(state.x == reference.x && state.v == reference.v)
        << "max |dx| " << (state.x - reference.x).cwiseAbs().maxCoeff();
    EXPECT_EQ(resolveCollisions(colliders, thickness, &pinned, split, &two), movedReference);
    EXPECT_TRUE(split.x == reference.x && split.v == reference.v)
        << "two threads: max |dx| " << (split.x - reference.x).cwiseAbs().maxCoeff();
}
