// Contact's broad phase (contact/broad_phase.h) against a search over every pair. On a crumpled
// grid whose particles move further in the step than its triangles are wide, every triangle's
// normal can flip, so no patch of the tree is flat and nothing may be skipped for its normals:
// the self pairs must then be exactly the vertex-triangle and edge-edge pairs more than
// kExcludedCells apart in the grid whose swept boxes overlap, each listed once. The boxes here are
// made from the positions alone, and "apart" from the grid's rows and columns. The search on two
// threads gives one thread's pairs, in its order.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "cloth/thread_pool.h"
#include "contact/broad_phase.h"

using namespace cloth;
using contact::BroadPhase;
using contact::Pair;

namespace {

struct Crumpled {
    Model model;
    Points y0, y1;
};

// An n x n grid of side `size` m, its particles jittered by up to `jitter` m along each axis at the
// start, each then moved `move` m in a random direction over the step. A triangle's normal can
// flip in the step (every direction in its cone, contact/cones.h) once each of its edges is no
// longer than the sum of its ends' half moves, `move`: the cases below keep every edge shorter.
Crumpled crumpled(int n, Scalar size, Scalar jitter, Scalar move, unsigned seed) {
    GridDesc g;
    g.nx = g.ny = n;
    g.width = g.height = size;
    Crumpled c{Model::fromGrid(g), {}, {}};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Scalar> unit(-1, 1);
    auto noise = [&](Scalar scale) { return Vec3(scale * unit(rng), scale * unit(rng), scale * unit(rng)); };
    c.y0 = c.model.restPositions(), c.y1 = c.y0;
    for (Index i = 0; i < c.model.particleCount(); ++i) {
        c.y0.col(i) += noise(jitter);
        Vec3 d = noise(1);
        while (d.norm() < 0.1) d = noise(1);
        c.y1.col(i) = c.y0.col(i) + move * d.normalized();
    }
    return c;
}

using PairKey = std::tuple<int, Index, Index>;  // kind, then the vertex and triangle, or the two edges in order

PairKey keyOf(const Pair& p) {
    if (p.kind == Pair::Kind::VertexTriangle) return {0, p.a, p.b};
    return {1, std::min(p.a, p.b), std::max(p.a, p.b)};
}

struct Box {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    void add(const Vec3& lo2, const Vec3& hi2) { lo = lo.cwiseMin(lo2), hi = hi.cwiseMax(hi2); }
    bool overlaps(const Box& b) const { return (lo.array() <= b.hi.array()).all() && (b.lo.array() <= hi.array()).all(); }
};

// Every pair the broad phase must list: more than kExcludedCells apart in rows or columns from
// each particle of the other primitive, and swept boxes (each particle's start and end, grown by
// margin / 2) that overlap.
std::set<PairKey> everyPair(const Crumpled& c, const std::vector<std::array<Index, 2>>& edges, Scalar margin) {
    const int nx = c.model.gridNx();
    auto box = [&](std::initializer_list<Index> ids) {
        Box b;
        for (Index i : ids)
            b.add(c.y0.col(i).cwiseMin(c.y1.col(i)).array() - margin / 2, c.y0.col(i).cwiseMax(c.y1.col(i)).array() + margin / 2);
        return b;
    };
    auto apart = [&](Index u, Index v) {
        return std::abs(u / nx - v / nx) > contact::kExcludedCells || std::abs(u % nx - v % nx) > contact::kExcludedCells;
    };
    std::set<PairKey> pairs;
    const auto& triangles = c.model.triangles();
    for (Index v = 0; v < c.model.particleCount(); ++v)
        for (Index t = 0; t < Index(triangles.size()); ++t) {
            const Triangle& tri = triangles[t];
            if (apart(v, tri[0]) && apart(v, tri[1]) && apart(v, tri[2]) && box({v}).overlaps(box({tri[0], tri[1], tri[2]})))
                pairs.insert({0, v, t});
        }
    for (Index e = 0; e < Index(edges.size()); ++e)
        for (Index f = e + 1; f < Index(edges.size()); ++f) {
            const auto &a = edges[e], &b = edges[f];
            if (apart(a[0], b[0]) && apart(a[0], b[1]) && apart(a[1], b[0]) && apart(a[1], b[1]) &&
                box({a[0], a[1]}).overlaps(box({b[0], b[1]})))
                pairs.insert({1, e, f});
        }
    return pairs;
}

// The broad phase's self pairs (every candidate kept), each checked to be listed once.
std::set<PairKey> broadPhasePairs(BroadPhase& broad, const Crumpled& c, Scalar margin) {
    std::vector<Scalar> moves(std::size_t(c.model.particleCount()));
    for (Index i = 0; i < c.model.particleCount(); ++i) moves[std::size_t(i)] = (c.y1.col(i) - c.y0.col(i)).norm();
    broad.refit(c.model, c.y0, c.y1, margin);
    broad.widen(c.y0, c.y1, moves, {});
    std::vector<Pair> out;
    const contact::Keep keepAll = [](Pair&) { return true; };
    broad.selfPairs(out, std::size_t(1) << 40, keepAll);
    std::set<PairKey> pairs;
    for (const Pair& p : out) EXPECT_TRUE(pairs.insert(keyOf(p)).second) << "a pair listed twice";
    return pairs;
}

}  // namespace

// Boxes that all overlap (every far pair is listed) and boxes that overlap in part, near each
// other in the grid (the search must find exactly those), on grids whose side is a power of two
// plus one and one that is not. The longest edge: a cell's diagonal plus twice the jitter's
// diagonal (2 cm against a 3 cm move; 25, 26 and 25 cm against 30).
TEST(BroadPhase, ACrumpledClothsSelfPairsAreEveryFarPairWhoseBoxesMeet) {
    struct Case {
        int n;
        Scalar size, jitter, move;
    };
    const Scalar margin = 0.01;
    for (const Case& k : {Case{9, 0.08, 0.002, 0.03}, Case{17, 2.0, 0.02, 0.3}, Case{12, 1.5, 0.02, 0.3}, Case{33, 4.0, 0.02, 0.3}}) {
        for (unsigned seed = 1; seed <= 3; ++seed) {
            SCOPED_TRACE("grid " + std::to_string(k.n) + ", side " + std::to_string(k.size) + ", seed " + std::to_string(seed));
            const Crumpled c = crumpled(k.n, k.size, k.jitter, k.move, seed);
            BroadPhase broad;
            const std::set<PairKey> found = broadPhasePairs(broad, c, margin);
            const std::set<PairKey> expected = everyPair(c, broad.edges(), margin);
            ASSERT_GT(expected.size(), 0u);
            EXPECT_EQ(found.size(), expected.size());
            std::vector<PairKey> missing, extra;
            std::set_difference(expected.begin(), expected.end(), found.begin(), found.end(), std::back_inserter(missing));
            std::set_difference(found.begin(), found.end(), expected.begin(), expected.end(), std::back_inserter(extra));
            EXPECT_TRUE(missing.empty()) << missing.size() << " pairs missed, the first of kind " << std::get<0>(missing.front())
                                         << ": " << std::get<1>(missing.front()) << ", " << std::get<2>(missing.front());
            EXPECT_TRUE(extra.empty()) << extra.size() << " pairs listed that the search over every pair does not";
        }
    }
}

// The search in stripes on two threads (contact/broad_phase_search.cpp) against one thread's: the
// same pairs in the same order, kept by a Keep that drops some, on a first search and on a second
// after another widen (the two leaves' kept pairs then come from the first); and with `most` under
// the candidates, the same count at which the search stops.
TEST(BroadPhase, OnTwoThreadsTheSelfPairsAndWhereTheSearchStopsAreOneThreads) {
    const Scalar margin = 0.01;
    const contact::Keep keep = [](Pair& p) {
        p.gap = Scalar(p.a) + 1e-3 * Scalar(p.b);
        return (p.a + p.b) % 3 != 0;
    };
    auto search = [&](const Crumpled& c, ParallelFor* loops, std::size_t most, std::vector<Pair>& second) {
        std::vector<Scalar> moves(std::size_t(c.model.particleCount()));
        for (Index i = 0; i < c.model.particleCount(); ++i) moves[std::size_t(i)] = (c.y1.col(i) - c.y0.col(i)).norm();
        BroadPhase broad;
        broad.refit(c.model, c.y0, c.y1, margin, loops);
        broad.widen(c.y0, c.y1, moves, {}, loops);
        std::vector<Pair> first;
        const std::size_t found = broad.selfPairs(first, most, keep, loops);
        broad.widen(c.y0, c.y1, moves, std::vector<std::uint8_t>(moves.size(), 1), loops);
        broad.selfPairs(second, most, keep, loops);
        second.insert(second.begin(), first.begin(), first.end());
        return found;
    };
    auto same = [](const std::vector<Pair>& a, const std::vector<Pair>& b) {
        if (a.size() != b.size()) return false;
        for (std::size_t k = 0; k < a.size(); ++k)
            if (a[k].kind != b[k].kind || a[k].a != b[k].a || a[k].b != b[k].b || a[k].gap != b[k].gap) return false;
        return true;
    };
    ThreadPool two(2);
    for (const unsigned seed : {1u, 2u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        const Crumpled c = crumpled(33, 4.0, 0.02, seed == 1 ? 0.3 : 0.25, seed);
        std::vector<Pair> one, both;
        const std::size_t all = search(c, nullptr, std::size_t(1) << 40, one);
        ASSERT_GT(one.size(), 1000u);
        EXPECT_EQ(search(c, &two, std::size_t(1) << 40, both), all);
        EXPECT_TRUE(same(one, both));
        for (const std::size_t most : {all / 2, all / 5, std::size_t(10)}) {
            std::vector<Pair> a, b;
            const std::size_t stopped = search(c, nullptr, most, a);
            EXPECT_GT(stopped, most);
            EXPECT_LE(stopped, all);
            EXPECT_EQ(search(c, &two, most, b), stopped) << "most " << most;
        }
    }
}

// Whether two adjacent nodes' cones merged are flat, decided from their axes' cosine against a
// bound (contact/cones.h, mergedWithin), against the merged cone itself (mergeCones): the same
// answer for cones at any angle, and for angles within 1e-12 to 1e-3 radians of the bound, where
// half of them are flat and half not.
TEST(BroadPhase, TwoConesAreFlatTogetherExactlyWhenTheirMergedConeIs) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<Scalar> unit(-1, 1), share(0, 1);
    auto randomAxis = [&] {
        Vec3 v;
        do v = Vec3(unit(rng), unit(rng), unit(rng));
        while (v.norm() < 0.1);
        return Vec3(v.normalized());
    };
    int flatNearTheBound = 0, near = 0;
    for (const Scalar flat : {0.087, 0.5}) {
        for (int k = 0; k < 200000; ++k) {
            const Scalar ca = flat + (1 - flat) * share(rng), cb = flat + (1 - flat) * share(rng);
            const Vec3 a = randomAxis();
            // The widest angle at which the two merged stay flat: twice what the wider leaves.
            const Scalar bound = 2 * (std::acos(flat) - std::acos(std::min(ca, cb)));
            const bool atTheBound = k % 2 == 1;
            const Scalar offset = std::pow(10.0, -3 - 9 * share(rng)) * (k % 4 == 1 ? 1 : -1);
            const Scalar angle = atTheBound ? bound + offset : M_PI * share(rng);
            if (angle < 0 || angle > M_PI) continue;
            const Vec3 across = a.cross(randomAxis()).normalized();
            const Vec3 b = (std::cos(angle) * a + std::sin(angle) * across).normalized();
            Vec3 axis;
            Scalar merged = -1;
            contact::mergeCones(a, ca, b, cb, axis, merged);
            const bool flatTogether = merged > flat;
            ASSERT_EQ(contact::mergedWithin(a, ca, contact::partnerCos(ca, flat), b, cb, contact::partnerCos(cb, flat), flat),
                      flatTogether)
                << "flat " << flat << ", cones " << ca << " and " << cb << ", angle " << angle << " (bound " << bound << ")";
            if (atTheBound) ++near, flatNearTheBound += flatTogether;
        }
    }
    EXPECT_GT(flatNearTheBound, near / 4);
    EXPECT_LT(flatNearTheBound, 3 * near / 4);
}
