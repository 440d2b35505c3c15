// The cloth's constraints (cloth/constraints.h): Provot's correction for one spring by hand; the
// promises of the stretch limit (the limit reached, pins still, momentum and the centroid kept,
// the same bits on threads); tethers against each particle's nearest pin at rest, found here by
// brute force (the move is radial and v changes by dx / h).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "physics_support.h"
#include "cloth/constraints.h"
#include "cloth/presets.h"
#include "cloth/thread_pool.h"

using namespace cloth;
using namespace cloth::test;

namespace {

// ---------------------------------------------------------------------------------------------
// Anti-stretch

Vec3 linearMomentum(const Model& model, const State& s) {
    Vec3 p = Vec3::Zero();
    for (Index i = 0; i < model.particleCount(); ++i) p += model.masses()[i] * s.v.col(i);
    return p;
}

Vec3 massMoment(const Model& model, const State& s) {  // sum m_i x_i
    Vec3 p = Vec3::Zero();
    for (Index i = 0; i < model.particleCount(); ++i) p += model.masses()[i] * s.x.col(i);
    return p;
}

Scalar maxStrain(const Model& model, const State& s) {
    Scalar worst = -1;
    for (const Spring& sp : model.springs())
        worst = std::max(worst, (s.x.col(sp.j) - s.x.col(sp.i)).norm() / sp.rest - 1);
    return worst;
}

// A flag stretched to 1.5 times its width (every horizontal spring 50% over rest), jittered,
// with random velocities; column 0 stays at rest so pins there leave the limit reachable.
Cloth stretchedFlag(unsigned seed) {
    HangingFlagDesc d;
    d.nx = 7;
    d.ny = 6;
    HangingFlag flag = makeHangingFlag(d);
    Cloth c{flag.model, flag.state};
    std::mt19937 rng(seed);
    const Scalar spacing = d.width / (d.nx - 1);
    for (Index i = 0; i < c.model.particleCount(); ++i) {
        if (i % d.nx == 0) continue;
        c.state.x(0, i) = d.poleTop.x() + 1.5 * (c.state.x(0, i) - d.poleTop.x());
        c.state.x.col(i) += randomVec(rng, -0.02 * spacing, 0.02 * spacing);
        c.state.v.col(i) = randomVec(rng, -1, 1);
    }
    return c;
}

}  // namespace

// =============================================================================================
// 3. Anti-stretch

TEST(PhysicsStretchLimit, OnePassShortensOneSpringToTheLimitSplitByInverseMass) {
    // Two triangles of different areas, so the ends of spring (0, 1) have different masses.
    // Only that spring is over the limit (50%); particles 2 and 3 sit close, every spring to
    // them compressed, so no other spring is corrected.
    const Points rest = (Points(3, 4) << 0, 1, 0, 3, /**/ 0, 0, 1, 3, /**/ 0, 0, 0, 0).finished();
    const Model model = Model::fromMesh(rest, {{0, 1, 2}, {1, 3, 2}}, 0.1, {10, 10, 1});
    const Index a = 0, b = 1;
    State state = State::atRest(model);
    state.x.col(b) = Vec3(1.5, 0, 0);
    state.x.col(2) = Vec3(0.75, 0.2, 0);
    state.x.col(3) = Vec3(0.75, 0.5, 0);
    state.v.col(a) = Vec3(0.3, -0.1, 0.2);
    state.v.col(b) = Vec3(-0.2, 0.4, 0.1);
    const std::vector<std::uint8_t> pinned(4, 0);
    const Scalar limit = 0.1, h = 0.01;
    const State before = state;

    EXPECT_EQ(StretchLimit().apply(model, pinned, limit, 1, h, state), 1);

    // By hand: the spring must lose 1.5 - 1.1 = 0.4 along its direction (+x), end a moving by
    // 0.4 m_b / (m_a + m_b) and end b by 0.4 m_a / (m_a + m_b): the lighter end moves more.
    const Scalar ma = model.masses()[a], mb = model.masses()[b];
    ASSERT_GT(std::abs(ma - mb), 0.1 * mb) << "masses should differ for this test";
    const Vec3 move[2] = {Vec3(0.4 * mb / (ma + mb), 0, 0), Vec3(-0.4 * ma / (ma + mb), 0, 0)};
    const Scalar mass[2] = {ma, mb};
    const Index ends[2] = {a, b};
    for (int e = 0; e < 2; ++e) {
        const Index p = ends[e];
        const Vec3 dx = state.x.col(p) - before.x.col(p), dv = state.v.col(p) - before.v.col(p);
        EXPECT_LE((dx - move[e]).norm(), 1e-14) << "end " << p << " (mass " << mass[e] << ") moved by "
                                                << dx.transpose() << ", expected " << move[e].transpose();
        // The velocity changes by the correction / h.
        EXPECT_LE((dv - move[e] / h).norm(), 1e-12) << "end " << p << ": velocity changed by " << dv.transpose()
                                                    << ", expected " << (move[e] / h).transpose();
    }
    EXPECT_NEAR((state.x.col(b) - state.x.col(a)).norm(), 1.1, 1e-14) << "spring length after the pass";
    for (Index i : {2, 3}) {
        EXPECT_EQ(state.x.col(i), before.x.col(i)) << "particle " << i;
        EXPECT_EQ(state.v.col(i), before.v.col(i)) << "particle " << i;
    }
}

TEST(PhysicsStretchLimit, EnoughPassesBringEverySpringWithinTheLimitAndPinsStayPut) {
    Cloth c = stretchedFlag(5);
    std::vector<std::uint8_t> pinned(c.model.particleCount(), 0);
    for (Index i = 0; i < c.model.particleCount(); i += c.model.gridNx()) pinned[i] = 1;
    const Scalar limit = 0.1, h = 1.0 / 60;
    ASSERT_GT(maxStrain(c.model, c.state), 0.45);
    const State before = c.state;

    EXPECT_GT(StretchLimit().apply(c.model, pinned, limit, 1000, h, c.state), 0);

    EXPECT_LE(maxStrain(c.model, c.state), limit + 1e-9);
    for (Index i = 0; i < c.model.particleCount(); ++i) {
        if (pinned[i]) {
            EXPECT_EQ(c.state.x.col(i), before.x.col(i)) << "pinned particle " << i << " moved";
            EXPECT_EQ(c.state.v.col(i), before.v.col(i)) << "pinned particle " << i << " changed velocity";
        }
        // Documented: each particle's velocity changes by its total correction / h.
        const Vec3 dx = c.state.x.col(i) - before.x.col(i), dv = c.state.v.col(i) - before.v.col(i);
        EXPECT_LE((dv - dx / h).norm(), 1e-9) << "particle " << i;
    }
}

TEST(PhysicsStretchLimit, WithoutPinsMomentumAndMassMomentAreKept) {
    // Each correction moves the two ends by amounts inversely proportional to their masses:
    // sum m_i x_i and (since v changes by the correction / h) sum m_i v_i are unchanged.
    Cloth c = stretchedFlag(9);
    const std::vector<std::uint8_t> none(c.model.particleCount(), 0);
    const Scalar h = 1.0 / 60;
    const Vec3 p0 = linearMomentum(c.model, c.state), moment0 = massMoment(c.model, c.state);
    const State before = c.state;

    EXPECT_GT(StretchLimit().apply(c.model, none, 0.1, 50, h, c.state), 0);

    EXPECT_GT((c.state.x - before.x).norm(), 0.1);  // it did move particles
    const Scalar momentumScale = c.model.totalMass() * (c.state.v - before.v).cwiseAbs().maxCoeff();
    EXPECT_LE((linearMomentum(c.model, c.state) - p0).norm(), 1e-12 * momentumScale)
        << "momentum before " << p0.transpose() << ", after " << linearMomentum(c.model, c.state).transpose();
    EXPECT_LE((massMoment(c.model, c.state) - moment0).norm(), 1e-12 * c.model.totalMass())
        << "sum m x before " << moment0.transpose() << ", after " << massMoment(c.model, c.state).transpose();
}

TEST(PhysicsStretchLimit, ThreadsSplitTheBlocksWithTheSameBits) {
    // 129 x 129: four blocks, which the pass splits between two threads.
    HangingFlagDesc d;
    d.nx = d.ny = 129;
    HangingFlag flag = makeHangingFlag(d);
    std::mt19937 rng(3);
    const Scalar spacing = d.width / (d.nx - 1);
    for (Index i = 0; i < flag.model.particleCount(); ++i) {
        if (i % d.nx == 0) continue;
        flag.state.x(0, i) = d.poleTop.x() + 1.3 * (flag.state.x(0, i) - d.poleTop.x());
        flag.state.x.col(i) += randomVec(rng, -0.2 * spacing, 0.2 * spacing);
    }
    std::vector<std::uint8_t> pinned(flag.model.particleCount(), 0);
    for (const Pin& p : flag.pins) pinned[p.particle] = 1;
    ThreadPool one(1), two(2);
    State serial = flag.state, split = flag.state;
    const int a = StretchLimit().apply(flag.model, pinned, 0.1, 4, 1.0 / 240, serial, &one);
    const int b = StretchLimit().apply(flag.model, pinned, 0.1, 4, 1.0 / 240, split, &two);
    EXPECT_GT(a, 10000) << "the pass should have work to split";
    EXPECT_EQ(a, b);
    EXPECT_TRUE(serial.x == split.x && serial.v == split.v) << "two threads changed bits: max |dx| "
                                                           << (serial.x - split.x).cwiseAbs().maxCoeff();
}

namespace {

// The stretch limit written out: every spring in Model::passSprings()'s order in every pass, until
// a pass corrects none, with the pass's arithmetic. What StretchLimit::apply gives bit for bit,
// however it finds the springs worth checking.
int everySpringEveryPass(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                         Scalar h, State& s) {
    const Scalar floor = std::nextafter(Scalar(1e-24), Scalar(0));
    int total = 0;
    for (int pass = 0; pass < passes; ++pass) {
        int corrections = 0;
        for (const PassSpring& sp : model.passSprings()) {
            const Scalar limit = (1 + maxStretch) * sp.rest;
            const Scalar dx = s.x(0, sp.j) - s.x(0, sp.i), dy = s.x(1, sp.j) - s.x(1, sp.i), dz = s.x(2, sp.j) - s.x(2, sp.i);
            const Scalar L2 = dx * dx + dy * dy + dz * dz;
            if (L2 <= std::max(limit * limit, floor)) continue;
            const Scalar L = std::sqrt(L2);
            const Scalar wi = pinned[sp.i] ? 0 : 1 / model.masses()[sp.i], wj = pinned[sp.j] ? 0 : 1 / model.masses()[sp.j];
            if (L <= limit || wi + wj == 0) continue;
            const Scalar f = (L - limit) / (L * (wi + wj));
            const Vec3 c(f * dx, f * dy, f * dz);
            s.x.col(sp.i) += wi * c, s.x.col(sp.j) -= wj * c;
            s.v.col(sp.i) += (wi / h) * c, s.v.col(sp.j) -= (wj / h) * c;
            ++corrections;
        }
        total += corrections;
        if (corrections == 0) break;
    }
    return total;
}

// An n x n flag at rest with `kicked` random free particles moved by up to 0.6 of the spacing.
Cloth kickedFlag(int n, int kicked, std::mt19937& rng) {
    HangingFlagDesc d;
    d.nx = d.ny = n;
    HangingFlag flag = makeHangingFlag(d);
    Cloth c{flag.model, flag.state};
    const Scalar spacing = d.width / (d.nx - 1);
    std::uniform_int_distribution<Index> any(0, c.model.particleCount() - 1);
    for (int k = 0; k < kicked; ++k) {
        const Index i = any(rng);
        if (i % n != 0) c.state.x.col(i) += randomVec(rng, -0.6 * spacing, 0.6 * spacing);
    }
    return c;
}

// The springs over the limit in `s`, as bits in pass order, with every `extra`-th spring besides.
SpringBits overTheLimit(const Model& model, const State& s, Scalar maxStretch, int extra) {
    const auto& springs = model.passSprings();
    SpringBits bits((springs.size() + 63) / 64, 0);
    for (std::size_t k = 0; k < springs.size(); ++k) {
        const Scalar L = (s.x.col(springs[k].j) - s.x.col(springs[k].i)).norm();
        if (L > (1 + maxStretch) * springs[k].rest * (1 - 1e-9) || k % std::size_t(extra) == 0)
            bits[k / 64] |= std::uint64_t(1) << (k % 64);
    }
    return bits;
}

}  // namespace

TEST(PhysicsStretchLimit, PassesGiveTheBitsOfCheckingEverySpringInEveryPass) {
    // A few particles kicked (few corrections: the passes mark the springs to check) and many
    // (every spring checked), in three calls on the same limit (moves of a call before must not
    // read as this one's); 129 x 129 has four blocks, on one thread and on two.
    ThreadPool one(1), two(2);
    for (const int n : {9, 33, 129})
        for (const int kicked : {3, 40, n * n / 2})
            for (ThreadPool* pool : {&one, &two}) {
                std::mt19937 rng{unsigned(n + kicked)};
                Cloth c = kickedFlag(n, kicked, rng);
                std::vector<std::uint8_t> pinned(c.model.particleCount(), 0);
                for (Index i = 0; i < c.model.particleCount(); i += n) pinned[i] = 1;
                StretchLimit limit;
                State written = c.state;
                for (int call = 0; call < 3; ++call) {
                    const int expected = everySpringEveryPass(c.model, pinned, 0.1, 4, 1.0 / 240, written);
                    EXPECT_EQ(limit.apply(c.model, pinned, 0.1, 4, 1.0 / 240, c.state, pool), expected)
                        << n << " x " << n << ", " << kicked << " kicked, call " << call;
                    ASSERT_TRUE(c.state.x == written.x && c.state.v == written.v)
                        << n << " x " << n << ", " << kicked << " kicked, call " << call << ": max |dx| "
                        << (c.state.x - written.x).cwiseAbs().maxCoeff();
                    for (Index i = 1 + call; i < c.model.particleCount(); i += 7 * n + 3)  // more kicks
                        if (i % n != 0) c.state.x.col(i) += Vec3(0.02, -0.01, 0.03), written.x.col(i) = c.state.x.col(i);
                }
            }
}

TEST(PhysicsStretchLimit, ACallersListOfTheSpringsOverTheLimitGivesTheSameBits) {
    // The springs over the limit (and every 50th besides), as a cheaper test would list them;
    // and through the constraint set, listed before its tethers move particles, whose springs it
    // must add: in the third case column 1 moved out of the flag's plane by 0.45 spacings leaves
    // every spring within its limit (none listed) but column 1 beyond its tether (2%), which pulls
    // it back towards the pole and its springs to column 2 some 15% long, over the limit of 10%.
    struct Case {
        int kicked;
        Constraints constraints;
    };
    for (const Case& test : {Case{5, {0.02, 0.1, 4}}, Case{60, {0.02, 0.1, 4}}, Case{0, {0.02, 0.1, 4}}}) {
        std::mt19937 rng{unsigned(test.kicked)};
        Cloth c = kickedFlag(33, test.kicked, rng);
        if (test.kicked == 0) {
            const Scalar spacing = (c.state.x.col(1) - c.state.x.col(0)).norm();
            for (Index p = 1; p < c.model.particleCount(); p += 33) c.state.x(2, p) += 0.45 * spacing;
        }
        std::vector<std::uint8_t> pinned(c.model.particleCount(), 0);
        std::vector<Pin> pins;
        for (Index i = 0; i < c.model.particleCount(); i += 33) pinned[i] = 1, pins.push_back({i, c.state.x.col(i)});
        const Constraints& k = test.constraints;
        const SpringBits listed = overTheLimit(c.model, c.state, k.stretchLimit, 50);

        State written = c.state, state = c.state;
        const int expected = everySpringEveryPass(c.model, pinned, k.stretchLimit, 4, 1.0 / 240, written);
        EXPECT_EQ(StretchLimit().apply(c.model, pinned, k.stretchLimit, 4, 1.0 / 240, state, nullptr, &listed), expected);
        EXPECT_TRUE(state.x == written.x && state.v == written.v) << test.kicked << " kicked";

        ConstraintSet set;
        set.set(k);
        written = c.state, state = c.state;
        Tethers tethers;
        const int moved = tethers.apply(c.model, pins, k.tether, 1.0 / 240, written);
        ASSERT_GT(moved, 0);
        const int corrected = everySpringEveryPass(c.model, pinned, k.stretchLimit, 4, 1.0 / 240, written);
        ConstraintHints hints;  // every tethered particle, the springs over the limit
        hints.springs = listed;
        for (Index k = 0; k < Index(tethers.tethered().size()); ++k) hints.tethers.push_back(k);
        EXPECT_EQ(set.apply(c.model, pins, 1.0 / 240, state, nullptr, &hints), moved + corrected);
        EXPECT_TRUE(state.x == written.x && state.v == written.v) << test.kicked << " kicked, with tethers: max |dx| "
                                                                  << (state.x - written.x).cwiseAbs().maxCoeff();
    }
}

// Long-range attachments, checked against each particle's nearest pin at rest, found here by
// brute force over every pin.
struct TetherCheck {
    Index anchor;
    Scalar rest;
};
std::vector<TetherCheck> nearestPins(const Model& model, const std::vector<Pin>& pins) {
    std::vector<TetherCheck> out(model.particleCount(), {-1, 0});
    for (Index i = 0; i < model.particleCount(); ++i) {
        Scalar best = std::numeric_limits<Scalar>::infinity();
        for (const Pin& p : pins) {
            const Scalar d = (model.restPositions().col(i) - model.restPositions().col(p.particle)).norm();
            if (d < best) best = d, out[i] = {p.particle, d};
        }
    }
    return out;
}

void expectTethered(const Model& model, const std::vector<Pin>& pins, const State& before, const State& after,
                    Scalar stretch, Scalar h) {
    const std::vector<TetherCheck> near = nearestPins(model, pins);
    int over = 0;
    for (Index i = 0; i < model.particleCount(); ++i) {
        const bool pinned = std::any_of(pins.begin(), pins.end(), [&](const Pin& p) { return p.particle == i; });
        const Vec3 anchor = before.x.col(near[i].anchor);
        const Scalar limit = (1 + stretch) * near[i].rest, was = (before.x.col(i) - anchor).norm();
        EXPECT_EQ(after.x.col(near[i].anchor), anchor) << "pin " << near[i].anchor << " moved";
        if (pinned || was <= limit) {
            EXPECT_EQ(after.x.col(i), before.x.col(i)) << "particle " << i << " within its bound moved";
            EXPECT_EQ(after.v.col(i), before.v.col(i)) << "particle " << i << " within its bound changed velocity";
            continue;
        }
        ++over;
        // Onto the sphere of radius limit around the anchor, along the line to the anchor.
        const Vec3 r = after.x.col(i) - anchor, r0 = before.x.col(i) - anchor;
        EXPECT_NEAR(r.norm(), limit, 1e-12) << "particle " << i;
        EXPECT_LE((r - r0 * (limit / was)).norm(), 1e-12) << "particle " << i << " did not move radially";
        const Vec3 dx = after.x.col(i) - before.x.col(i), dv = after.v.col(i) - before.v.col(i);
        EXPECT_LE((dv - dx / h).norm(), 1e-9) << "particle " << i << ": velocity changed by " << dv.transpose();
    }
    EXPECT_GT(over, 0) << "no particle was over its bound: the test shows nothing";
}

TEST(PhysicsTethers, ParticlesOverTheirBoundMoveRadiallyOntoItAndTheRestStay) {
    Cloth c = stretchedFlag(5);
    const std::vector<Pin> column = pinColumn(c.model);
    const Scalar stretch = 0.1, h = 1.0 / 240;
    const State before = c.state;
    Tethers tethers;
    const int moved = tethers.apply(c.model, column, stretch, h, c.state);
    EXPECT_GT(moved, 0);
    expectTethered(c.model, column, before, c.state, stretch, h);

    // Other pins (the last column, stretched away from the rest): the anchors follow them.
    std::vector<Pin> last;
    const Index nx = c.model.gridNx();
    for (Index i = nx - 1; i < c.model.particleCount(); i += nx) last.push_back({i, before.x.col(i), Vec3::Zero()});
    State again = before;
    tethers.apply(c.model, last, stretch, h, again);
    expectTethered(c.model, last, before, again, stretch, h);

    // The particles split between two threads.
    ThreadPool two(2);
    State split = before;
    EXPECT_EQ(tethers.apply(c.model, column, stretch, h, split, &two), moved);
    expectTethered(c.model, column, before, split, stretch, h);
}

TEST(PhysicsTethers, AStepWithTethersEndsWithinTheBoundAndOneWithoutDoesNot) {
    // The paper's step on a flag whose pole jumps 0.5 m sideways: without tethers particles are
    // left far beyond 10% of their distance to the pole; with them none is.
    for (const std::string spec : {"kangcho:iterations=1", "exact", "explicit:substeps=4"}) {
        HangingFlagDesc d;
        d.nx = 9;
        d.ny = 7;
        HangingFlag flag = makeHangingFlag(d);
        std::vector<Pin> pins = pinColumn(flag.model);
        for (Pin& p : pins) p.x += Vec3(0, 0, 0.5);
        const StepInput input = stepInput(1.0 / 240, pins, nullptr);
        Scalar worst[2] = {0, 0};
        for (int on = 0; on < 2; ++on) {
            auto solver = solverFor(spec);
            ASSERT_TRUE(solver);
            Constraints tethers;
            tethers.tether = on ? 0.1 : 0;
            solver->setConstraints(tethers);
            State state = flag.state;
            ASSERT_EQ(solver->step(flag.model, {}, state, input).status, StepStatus::Ok) << spec;
            const std::vector<TetherCheck> near = nearestPins(flag.model, pins);
            for (Index i = 0; i < flag.model.particleCount(); ++i)
                if (near[i].rest > 0)
                    worst[on] = std::max(worst[on], (state.x.col(i) - state.x.col(near[i].anchor)).norm() / near[i].rest);
        }
        EXPECT_GT(worst[0], 1.5) << spec << ": without tethers the jump should leave particles far behind";
        EXPECT_LE(worst[1], 1.1 + 1e-12) << spec << ": with tether=0.1";
    }
}
