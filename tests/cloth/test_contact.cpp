// The contact stage (cloth/contact.h) against geometry written here: a particle at 100 m/s does not
// tunnel through a 1 cm capsule, an edge whose ends pass either side of a capsule is caught, a
// teleport of the carrier moves nothing, and pinned particles never move. Each case is also run
// without contact, to show that it would cross.

#include <gtest/gtest.h>

#include <cmath>

#include "cloth/contact.h"
#include "cloth/crossings.h"
#include "cloth/thread_pool.h"

using namespace cloth;

namespace {

// A small grid lying in the plane z = 0 (particles 1 cm .. apart), its first particle pinned.
struct Sheet {
    Model model;
    State state;
    std::vector<std::uint8_t> pinned;
};

Sheet sheet(int nx, int ny, Scalar width, Scalar height, const Vec3& origin) {
    GridDesc g;
    g.nx = nx, g.ny = ny, g.width = width, g.height = height, g.origin = origin;
    g.axisU = Vec3::UnitX(), g.axisV = Vec3::UnitY();
    Model m = Model::fromGrid(g);
    State s = State::atRest(m);
    std::vector<std::uint8_t> pinned(std::size_t(m.particleCount()), 0);
    pinned[0] = 1;
    return {std::move(m), std::move(s), std::move(pinned)};
}

// A capsule along z through (cx, cy), radius r, 2 m long.
Collider rod(Scalar cx, Scalar cy, Scalar r) {
    Collider c;
    c.shape = Collider::Shape::Capsule;
    c.center = Vec3(cx, cy, 0);
    c.axis = Vec3::UnitZ();
    c.halfExtents = Vec3(1, 0, 0);
    c.radius = r;
    return c;
}

// The distance from p to the rod's axis (an infinite line along z through (cx, cy)).
Scalar fromAxis(const Vec3& p, Scalar cx, Scalar cy) { return std::hypot(p.x() - cx, p.y() - cy); }

// The distance from the segment a-b (in the plane z = 0) to the point (cx, cy).
Scalar segmentFromAxis(const Vec3& a, const Vec3& b, Scalar cx, Scalar cy) {
    const Vec3 c(cx, cy, a.z()), d = b - a;
    const Scalar t = std::clamp((c - a).dot(d) / d.squaredNorm(), Scalar(0), Scalar(1));
    return (a + t * d - c).norm();
}

ContactSettings on() {
    ContactSettings s;
    s.enabled = true;
    s.self = false;
    s.thickness = 0.002;
    return s;
}

}  // namespace

TEST(Contact, AParticleAt100MetresPerSecondDoesNotTunnelThroughACentimetreCapsule) {
    // A 2 x 2 sheet 10 cm across; its far corner (particle 3) flies at 100 m/s along -x for one
    // 1/60 s step: 1.67 m, straight through a rod of 1 cm radius standing 30 cm in its way.
    for (const bool contact : {false, true}) {
        Sheet s = sheet(2, 2, 0.1, 0.1, Vec3(0, 0, 0));
        const Collider pole = rod(-0.2, 0.1, 0.01);
        const Points start = s.state.x;
        const Scalar h = 1.0 / 60;
        s.state.v.col(3) = Vec3(-100, 0, 0);
        s.state.x.col(3) += h * s.state.v.col(3);
        if (contact) {
            ContactStage stage;
            const ContactReport r = stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, RigidFrame{}, {pole}, on(), h);
            EXPECT_GT(r.limited, 0);
            // Stopped on the near side, never through: right of the rod, on or outside its surface
            // (it closes the gap by 90% of what is left in each of 64 sub-intervals).
            constexpr Scalar rounding = 1e-12;
            EXPECT_GE(s.state.x(0, 3), -0.2 + 0.01 - rounding);
            EXPECT_GE(fromAxis(s.state.x.col(3), -0.2, 0.1), 0.01 - rounding);
            // The edges from it never passed through the rod either.
            EXPECT_GE(segmentFromAxis(s.state.x.col(1), s.state.x.col(3), -0.2, 0.1), 0.01 - rounding);
        } else {
            EXPECT_LT(s.state.x(0, 3), -0.2 - 0.01);  // without contact it ends beyond the rod
        }
    }
}

TEST(Contact, AnEdgeWhoseEndsPassEitherSideOfACapsuleIsCaught) {
    // A 2 x 2 sheet 20 cm tall moving 30 cm along -x in one step, its left edge (particles 0 and
    // 2, at y = 0 and 0.2) sweeping over a rod at y = 0.1: the ends pass either side of it, the
    // edge's middle through it. Particle 0 is not pinned here: particle 1 is.
    for (const bool contact : {false, true}) {
        Sheet s = sheet(2, 2, 0.1, 0.2, Vec3(0, 0, 0));
        s.pinned.assign(4, 0);
        const Collider pole = rod(-0.1, 0.1, 0.02);
        const Points start = s.state.x;
        for (Index i : {0, 2, 3}) s.state.x(0, i) -= 0.3;
        if (contact) {
            ContactStage stage;
            s.pinned[1] = 1;
            stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, RigidFrame{}, {pole}, on(), 1.0 / 240);
            // The edge stopped before the rod: no point of it within the rod's radius, and no end past it.
            EXPECT_GE(segmentFromAxis(s.state.x.col(0), s.state.x.col(2), -0.1, 0.1), 0.02);
            EXPECT_GT(s.state.x(0, 0), -0.1);
        } else {
            EXPECT_LT(s.state.x(0, 0), -0.1 - 0.02);  // without contact the edge ends beyond the rod: through it
        }
    }
}

TEST(Contact, ATeleportOfTheCarrierMovesNothingAndPinsStayPut) {
    // The carrier, and the cloth with it, jumps 1 m and turns 90 degrees in one step: in the
    // carrier's frame nothing moved, so contact changes nothing, however close the rod stands.
    Sheet s = sheet(3, 3, 0.1, 0.1, Vec3(0, 0, 0));
    const Collider pole = rod(-0.025, 0.05, 0.02);  // 5 mm from the sheet's left edge
    RigidFrame to;
    to.position = Vec3(1, 0, 0);
    to.rotation = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ());
    const Points start = s.state.x;
    for (Index i = 0; i < s.model.particleCount(); ++i) s.state.x.col(i) = to.point(start.col(i));
    const Points moved = s.state.x;
    ContactStage stage;
    ContactSettings set = on();
    set.self = true;
    const ContactReport r = stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, to, {pole}, set, 1.0 / 240);
    EXPECT_EQ(r.limited, 0);
    EXPECT_LT((s.state.x - moved).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(s.state.x.col(0), moved.col(0));  // pinned: never moved
}

TEST(Contact, AParticlePressedIntoACapsuleStepAfterStepKeepsAGapOfATenthOfTheThickness) {
    // Particle 3 is driven 1 cm into a rod of 1 cm radius in each of 200 steps. The bounds share
    // out the gap less a tenth of the thickness, so the gap to the rod's surface never closes
    // below that: shares of the whole gap would close 90% of it in every sub-interval, down to a
    // gap that rounding flips into a crossing.
    Sheet s = sheet(2, 2, 0.1, 0.1, Vec3(0, 0, 0));
    const ContactSettings set = on();
    const Collider pole = rod(0.1 + 0.01 + 0.005, 0.1, 0.01);  // 5 mm right of particle 3, at (0.1, 0.1)
    ContactStage stage;
    Scalar closest = 1;
    for (int step = 0; step < 200; ++step) {
        const Points start = s.state.x;
        s.state.x(0, 3) += 0.01;
        stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, RigidFrame{}, {pole}, set, 1.0 / 240);
        closest = std::min(closest, fromAxis(s.state.x.col(3), 0.115, 0.1) - 0.01);
    }
    EXPECT_GE(closest, 0.1 * set.thickness * (1 - 1e-9));
    EXPECT_LT(closest, 0.2 * set.thickness);  // pressed close: the floor is what holds it
}

TEST(Contact, ACloudOfParticlesTooCloseToBoundKeepsItsStart) {
    // A cloth blown apart (an unstable solver): every free particle of a 17x17 sheet thrown into a
    // 10 cm cube beside a rod. Its tens of thousands of self pairs would take seconds a step to
    // bound; past 128 a particle the stage says so and leaves every free particle where the step
    // started (uncrossed, out of the rod). A flat sheet's step is bounded as usual.
    Sheet s = sheet(17, 17, 0.5, 0.5, Vec3(0, 0, 0));
    const Collider pole = rod(0.6, 0.05, 0.01);
    ContactSettings set = on();
    set.self = true;
    ContactStage stage;
    const Points start = s.state.x;
    State flat = s.state;
    flat.x.row(2).array() += 0.001;
    const ContactReport quiet = stage.apply(s.model, s.pinned, start, flat, RigidFrame{}, RigidFrame{}, {pole}, set, 1.0 / 240);
    EXPECT_EQ(quiet.overloaded, 0);
    EXPECT_EQ(flat.x(2, 5), 0.001);
    unsigned seed = 7;
    auto unit = [&] { return Scalar((seed = seed * 1103515245u + 12345u) >> 8 & 0xffff) / 0xffff; };
    for (Index i = 1; i < s.model.particleCount(); ++i)
        s.state.x.col(i) = Vec3(0.5 + 0.1 * unit(), 0.1 * unit(), 0.1 * unit() - 0.05);
    const ContactReport r = stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, RigidFrame{}, {pole}, set, 1.0 / 240);
    EXPECT_EQ(r.overloaded, 1);
    for (Index i = 0; i < s.model.particleCount(); ++i) EXPECT_EQ(s.state.x.col(i), start.col(i)) << "particle " << i;
}

TEST(Contact, AParticlePressedOnACapsuleSlidesAlongItFreely) {
    // Particle 3 is pressed onto a rod until only a tenth of the thickness is left, then driven 1 cm
    // along the rod's axis in each of 10 steps. Its bound keeps it off the rod across the rod's
    // surface only, so it follows its target along the rod: a bound on the length of its move
    // (0.9 times the gap less the floor, here about none) would hold it where it was pressed.
    Sheet s = sheet(2, 2, 0.1, 0.1, Vec3(0, 0, 0));
    const ContactSettings set = on();
    const Collider pole = rod(0.1 + 0.01 + 0.005, 0.1, 0.01);
    ContactStage stage;
    auto step = [&](const Vec3& push) {
        const Points start = s.state.x;
        s.state.x.col(3) += push;
        stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, RigidFrame{}, {pole}, set, 1.0 / 240);
    };
    for (int k = 0; k < 50; ++k) step(Vec3(0.01, 0, 0));
    const Vec3 pressed = s.state.x.col(3);
    EXPECT_LT(fromAxis(pressed, 0.115, 0.1) - 0.01, 0.2 * set.thickness);
    for (int k = 0; k < 10; ++k) step(Vec3(0, 0, 0.01));
    EXPECT_NEAR(s.state.x(2, 3) - pressed.z(), 0.1, 1e-9);
    EXPECT_GE(fromAxis(s.state.x.col(3), 0.115, 0.1) - 0.01, 0.1 * set.thickness * (1 - 1e-9));
}

TEST(Contact, AParticleSlidingRoundACapsuleIsStoppedByClothBesideItsStraightPath) {
    // Particle 15 of an 8 x 2 sheet moves 6 cm along x, straight through a short rod of 2 cm
    // radius: contact slides it round the rod's top, 2 cm off its straight path. There stands a wall
    // of the same cloth (a triangle of the sheet's first cells, in the plane x = 0, its lower edge
    // through the rod), beyond the reach the step's broad phase searches around that path. An edge
    // from particle 15 to a neighbour just behind the wall would end through it if the particle got
    // round. Every other particle stands still, far away.
    Sheet s = sheet(8, 2, 0.7, 0.1, Vec3(0, 0, 0));
    s.pinned.assign(16, 0);
    Collider pole = rod(0, 0, 0.02);
    pole.halfExtents = Vec3(0.005, 0, 0);  // 1 cm long: the wall's ends are outside it
    for (Index i = 0; i < 16; ++i) s.state.x.col(i) = Vec3(-1 - 0.1 * (i % 8), 0.1 * (i / 8), -1);
    const Triangle wall = s.model.triangles()[0];  // columns 0 and 1
    ASSERT_LE(std::max({wall[0] % 8, wall[1] % 8, wall[2] % 8}), 1);
    s.state.x.col(wall[0]) = Vec3(0, 0.015, -0.03), s.state.x.col(wall[1]) = Vec3(0, 0.015, 0.03);
    s.state.x.col(wall[2]) = Vec3(0, 0.05, 0);
    Scalar side = -0.01;
    for (Index j : {6, 7, 14}) s.state.x.col(j) = Vec3(-0.01, 0.03, side), side += 0.01;
    s.state.x.col(15) = Vec3(-0.03, 0, 0);
    const Points start = s.state.x;
    s.state.x.col(15) = Vec3(0.03, 0.002, 0);
    CrossingScene scene;
    scene.capsules.push_back({Vec3(0, 0, -0.005), Vec3(0, 0, 0.005), 0.02});
    ASSERT_EQ(countCrossings(s.model, start, scene).selfEdges, 0);
    ASSERT_GT(countCrossings(s.model, s.state.x, scene).selfEdges, 0);  // straight through: the edge 14-15 crosses
    const State end = s.state;
    for (const auto bounds : {ContactSettings::SelfBounds::Lengths, ContactSettings::SelfBounds::HalfSpaces}) {
        ContactSettings set = on();
        set.self = true, set.selfBounds = bounds;
        ContactStage stage;
        s.state = end;
        const ContactReport r = stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, RigidFrame{}, {pole}, set, 1.0 / 240);
        EXPECT_GT(r.regionCuts, 0);
        EXPECT_GT(r.passes, 0);
        EXPECT_GT(s.state.x(1, 15), 0.01);  // it did slide up round the rod
        EXPECT_EQ(countCrossings(s.model, s.state.x, scene).selfEdges, 0);
    }
}

TEST(Contact, LayersPressedTogetherSlideAlongEachOtherWithHalfSpaceBoundsAndAreHeldWithLengthBounds) {
    // An 8 x 2 sheet folded over: its first three columns (pinned) lie flat, its last three 1.5 mm
    // above them (less than the 2 mm thickness), the two between off to the side. The top layer is
    // driven 1 cm along the layers in one step. A bound on the length of each move (0.45 times the
    // gap less the floor, about 0.6 mm a sub-interval) holds it back; a half-space bounds only its
    // move towards the layer below, so it slides over nine tenths of the centimetre (where it passes
    // the lower layer's end, the direction between closest points leans back). Neither ends crossed.
    for (const auto bounds : {ContactSettings::SelfBounds::Lengths, ContactSettings::SelfBounds::HalfSpaces}) {
        Sheet s = sheet(8, 2, 0.14, 0.02, Vec3(0, 0, 0));
        s.pinned.assign(16, 0);
        for (Index i = 0; i < 16; ++i) {
            const int c = int(i % 8), r = int(i / 8);
            if (c <= 2) s.state.x.col(i) = Vec3(0.02 * c, 0.02 * r, 0), s.pinned[i] = 1;
            else if (c >= 5) s.state.x.col(i) = Vec3(0.02 * (c - 5), 0.02 * r, 0.0015);
            else s.state.x.col(i) = Vec3(0.1 + 0.02 * (c - 3), 0.02 * r, 0.05);
        }
        const Points start = s.state.x;
        for (Index i = 0; i < 16; ++i)
            if (i % 8 >= 5) s.state.x(0, i) += 0.01;
        ContactSettings set = on();
        set.self = true, set.selfBounds = bounds;
        ContactStage stage;
        stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, RigidFrame{}, {}, set, 1.0 / 240);
        const Scalar slid = s.state.x(0, 6) - start(0, 6);  // the top layer's middle
        if (bounds == ContactSettings::SelfBounds::HalfSpaces) EXPECT_GT(slid, 0.009);
        else EXPECT_LT(slid, 0.005);
        EXPECT_GE(s.state.x(2, 6), 0.0015 - 1e-12);  // pushed up if anything, never down into the layer
        EXPECT_EQ(countCrossings(s.model, s.state.x, CrossingScene{}).selfEdges, 0);
    }
}


TEST(Contact, AFoldedClothOnTwoThreadsGetsTheBitsOfOneThread) {
    // A 65 x 65 sheet 1 m across (large enough that the application's loops run on the threads),
    // its right half folded over its left 2 cm above it and pressed 3 cm down through it in the
    // step: thousands of self pairs, searched in stripes on two threads and gathered in the tree's
    // order, and sub-intervals that push. Any change of order or of a box would change the bits.
    ContactSettings set = on();
    set.self = true, set.thickness = 0.015;
    auto folded = [](Sheet& s, Scalar lift) {
        const int n = s.model.gridNx(), m = (n - 1) / 2;
        for (int r = 0; r < n; ++r)
            for (int c = m + 1; c < n; ++c) s.state.x.col(r * n + c) = s.state.x.col(r * n + 2 * m - c) + Vec3(0, 0, lift);
    };
    auto run = [&](ParallelFor* loops) {
        Sheet s = sheet(65, 65, 1.0, 1.0, Vec3(0, 0, 0));
        folded(s, 0.02);
        const Points start = s.state.x;
        folded(s, -0.01);
        ContactStage stage;
        const ContactReport r = stage.apply(s.model, s.pinned, start, s.state, RigidFrame{}, RigidFrame{}, {}, set, 1.0 / 240, loops);
        return std::pair{s.state, r};
    };
    const auto [one, r1] = run(nullptr);
    ThreadPool two(2);
    const auto [both, r2] = run(&two);
    EXPECT_GT(r1.selfPairs, 1000);
    EXPECT_GT(r1.limited, 0);
    EXPECT_EQ(r2.selfPairs, r1.selfPairs);
    EXPECT_EQ(r2.subintervals, r1.subintervals);
    EXPECT_TRUE(both.x == one.x);
    EXPECT_TRUE(both.v == one.v);
}
