// The crossing checker (cloth/crossings.h): each count against a setup whose answer follows from
// its geometry (written out here), and the self count against a brute-force count over every
// pair with this file's own plain double predicate.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "cloth/crossings.h"

using namespace cloth;

namespace {

// A 17 x 17 flag, 1.6 m square in the plane z = 0: column c at x = 0.1 c, row r at y = -0.1 r.
Model flag(int n = 17) {
    GridDesc g;
    g.nx = g.ny = n;
    g.width = g.height = 0.1 * (n - 1);
    return Model::fromGrid(g);
}

// The flag's positions written from the indices: column c, row r at (0.1 c, -0.1 r, 0).
Points flat(int n = 17) {
    Points x(3, n * n);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) x.col(r * n + c) = Vec3(0.1 * c, -0.1 * r, 0);
    return x;
}

// Folded through itself: the left half (columns 0..8) stays flat; the right half (9..16) is
// turned over onto it (x' = 0.1 (16 - c)), moved down 3 cm (y' = -0.1 r - 0.03) and tilted,
// z' = 0.1 x' - 0.035: its plane meets z = 0 along x' = 0.35, halfway between columns 3 and 4,
// with columns 12 (z' = +5 mm) and 13 (z' = -5 mm) on either side.
//   Right-half edges between columns 12 and 13 cross z = 0 at x' = 0.35: the horizontal ones at
// y = -0.1 r - 0.03 (r = 0..15 land on the left half, r = 16 below it), the diagonals at their
// middles, y = -0.1 r - 0.08 (r = 0..15): 32 points strictly inside left triangles (at (0.5, 0.3)
// and (0.5, 0.8) of a cell, off its diagonal either way).
//   Left-half edges between columns 3 and 4 cross the tilted plane at x = 0.35: the horizontal
// ones at y = -0.1 r (r = 1..16 land on the right half, r = 0 above it), the diagonals at
// y = -0.1 r - 0.05 (r = 0..15): 32 more, at (0.5, 0.7) and (0.5, 0.2) of a right-half cell.
// Every such pair is 8 or more columns apart: 64 crossings.
constexpr int kFoldCrossings = 64;
Points foldedThrough() {
    Points x = flat();
    for (int r = 0; r < 17; ++r)
        for (int c = 9; c < 17; ++c) {
            const double xf = 0.1 * (16 - c);
            x.col(r * 17 + c) = Vec3(xf, -0.1 * r - 0.03, 0.1 * xf - 0.035);
        }
    return x;
}

// Folded over, the right half 1 cm above the left one, parallel to it: nothing crosses.
Points foldedParallel() {
    Points x = flat();
    for (int r = 0; r < 17; ++r)
        for (int c = 9; c < 17; ++c) x.col(r * 17 + c) = Vec3(0.1 * (16 - c), -0.1 * r, 0.01);
    return x;
}

Points transformed(const Points& x, const Mat3& rotation, const Vec3& shift) {
    Points y = rotation * x;
    y.colwise() += shift;
    return y;
}

// ---------------------------------------------------------------------------------------------
// A brute-force self count: every unique edge against every triangle, far apart by the given
// rule, crossing by signed volumes in plain double.

double volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return (b - a).cross(c - a).dot(d - a);
}

bool crossesPlain(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    const double vp = volume(a, b, c, p), vq = volume(a, b, c, q);
    if (!(vp * vq < 0)) return false;
    const double s0 = volume(p, q, a, b), s1 = volume(p, q, b, c), s2 = volume(p, q, c, a);
    return (s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0);
}

std::set<std::pair<Index, Index>> uniqueEdges(const Model& m) {
    std::set<std::pair<Index, Index>> edges;
    for (const Triangle& t : m.triangles())
        for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    return edges;
}

// Graph distances between every pair of particles over the mesh edges (BFS from each).
std::vector<std::vector<int>> meshDistances(const Model& m) {
    const int n = m.particleCount();
    std::vector<std::vector<Index>> nbr(n);
    for (const auto& [p, q] : uniqueEdges(m)) {
        nbr[p].push_back(q);
        nbr[q].push_back(p);
    }
    std::vector<std::vector<int>> dist(n, std::vector<int>(n, -1));
    for (int s = 0; s < n; ++s) {
        std::vector<int> queue{s};
        dist[s][s] = 0;
        for (std::size_t k = 0; k < queue.size(); ++k)
            for (const Index w : nbr[queue[k]])
                if (dist[s][w] < 0) {
                    dist[s][w] = dist[s][queue[k]] + 1;
                    queue.push_back(w);
                }
    }
    return dist;
}

int bruteSelfCount(const Model& m, const Points& x) {
    const int nx = m.gridNx();
    const auto dist = nx > 0 ? std::vector<std::vector<int>>{} : meshDistances(m);
    auto apart = [&](Index u, Index w) {
        if (nx == 0) return dist[u][w] < 0 || dist[u][w] >= 3;
        return std::max(std::abs(u / nx - w / nx), std::abs(u % nx - w % nx)) >= 3;
    };
    int count = 0;
    for (const auto& [p, q] : uniqueEdges(m))
        for (const Triangle& t : m.triangles()) {
            bool far = true;
            for (const Index w : t) far = far && apart(p, w) && apart(q, w);
            if (far && crossesPlain(x.col(p), x.col(q), x.col(t[0]), x.col(t[1]), x.col(t[2]))) ++count;
        }
    return count;
}

// The flag crumpled at random: squeezed into a third of its size and shaken in every direction
// by up to 1.5 cells, so that it passes through itself many times.
Points crumpled(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> shake(-0.15, 0.15);
    Points x = flat(n) * 0.33;
    for (Eigen::Index i = 0; i < x.cols(); ++i) x.col(i) += Vec3(shake(rng), shake(rng), shake(rng));
    return x;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Self crossings.

TEST(Crossings, FlatFlagNearItsPoleBodyAndGroundHasNone) {
    const Model m = flag();
    CrossingScene scene;
    scene.capsules.push_back({Vec3(-0.05, 0.5, 0), Vec3(-0.05, -2, 0), 0.03});  // 2 cm off column 0
    CrossingScene::Box body;
    body.center = Vec3(0.8, -0.8, 0.25);  // 5 cm behind the flag
    body.halfExtents = Vec3(1, 1, 0.2);
    scene.boxes.push_back(body);
    scene.grounds.push_back({Vec3(0, -1.61, 0), Vec3::UnitY()});  // 1 cm under the lowest row
    const CrossingCounts counts = countCrossings(m, flat(), scene);
    EXPECT_EQ(counts.poleEdges, 0);
    EXPECT_EQ(counts.selfEdges, 0);
    EXPECT_EQ(counts.bodyEdges, 0);
    EXPECT_EQ(counts.groundParticles, 0);
    EXPECT_EQ(counts.total(), 0);
}

TEST(Crossings, FlagFoldedThroughItselfCrossesAtEveryEdgeThatStraddlesTheFold) {
    const Model m = flag();
    EXPECT_EQ(countCrossings(m, foldedThrough(), {}).selfEdges, kFoldCrossings);
    // The same shape turned and moved anywhere.
    const Mat3 turn = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    EXPECT_EQ(countCrossings(m, transformed(foldedThrough(), turn, Vec3(3, -20, 7)), {}).selfEdges,
              kFoldCrossings);
    // As a plain mesh (no grid): the same pairs, all far apart in the mesh graph too.
    const Model mesh = Model::fromMesh(m.restPositions(), m.triangles(), 0.3, {});
    EXPECT_EQ(countCrossings(mesh, foldedThrough(), {}).selfEdges, kFoldCrossings);
}

TEST(Crossings, FlagFoldedIntoParallelLayersOneCentimetreApartHasNone) {
    const Model m = flag();
    EXPECT_EQ(countCrossings(m, foldedParallel(), {}).total(), 0);
    // 1 cm apart and down 3 cm: every pair of layers' cells still apart, nothing touches.
    Points x = foldedParallel();
    for (int r = 0; r < 17; ++r)
        for (int c = 9; c < 17; ++c) x(1, r * 17 + c) -= 0.03;
    EXPECT_EQ(countCrossings(m, x, {}).total(), 0);
}

TEST(Crossings, CrumpledFlagCountsEveryCrossingPairOnce) {
    for (const unsigned seed : {1u, 2u, 3u}) {
        const Model m = flag();
        const Points x = crumpled(17, seed);
        const int brute = bruteSelfCount(m, x);
        EXPECT_GT(brute, 100) << "seed " << seed;
        EXPECT_EQ(countCrossings(m, x, {}).selfEdges, brute) << "seed " << seed;
        // A particle thrown 100 m away: its triangles span too many cells for the grid.
        Points far = x;
        far.col(5 * 17 + 5) = Vec3(100, 30, -50);
        EXPECT_EQ(countCrossings(m, far, {}).selfEdges, bruteSelfCount(m, far)) << "seed " << seed;
    }
}

// A particle lost to NaN: the pairs it is in cannot be judged, every other pair still is.
TEST(Crossings, CrumpledFlagWithANanParticleCountsTheOtherPairs) {
    const Model m = flag();
    Points x = crumpled(17, 5);
    x.col(8 * 17 + 8) = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    const int brute = bruteSelfCount(m, x);  // NaN fails every comparison of the plain test
    EXPECT_GT(brute, 100);
    EXPECT_EQ(countCrossings(m, x, {}).selfEdges, brute);
}

TEST(Crossings, CrumpledPlainMeshCountsPairsThreeEdgesApart) {
    const Model grid = flag(9);
    const Model mesh = Model::fromMesh(grid.restPositions(), grid.triangles(), 0.3, {});
    const Points x = crumpled(9, 4);
    const int brute = bruteSelfCount(mesh, x);
    EXPECT_GT(brute, 10);
    EXPECT_EQ(countCrossings(mesh, x, {}).selfEdges, brute);
}

// A needle edge PQ through triangle ABC, the needle's triangle GPQ joined to C by a chain of
// `links` triangles: C and G are `links` edges apart, C and P links + 1. The needle PQ crosses
// ABC at its middle, and so does GP (at (0.05, 0, 0)); nothing else crosses. GP counts when
// links >= 3, PQ when links >= 2.
Model needleThroughTriangle(int links, Points& x) {
    std::vector<Vec3> v = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};  // A, B, C
    std::vector<Triangle> tris = {{0, 1, 2}};
    Index previous = 2;
    for (int k = 1; k <= links; ++k) {
        v.push_back({1, 1.0 + k, 2.0 * k + 1});  // a side vertex high above ABC
        const Index side = Index(v.size() - 1);
        v.push_back(k == links ? Vec3(0.2, 0, 3) : Vec3(0, 2, 2.0 * k + 2));  // the last one is G
        tris.push_back({previous, side, Index(v.size() - 1)});
        previous = Index(v.size() - 1);
    }
    v.push_back({0, 0, -1});  // P
    v.push_back({0, 0, 1});   // Q
    tris.push_back({previous, Index(v.size() - 2), Index(v.size() - 1)});
    x.resize(3, Eigen::Index(v.size()));
    for (std::size_t i = 0; i < v.size(); ++i) x.col(Eigen::Index(i)) = v[i];
    return Model::fromMesh(x, tris, 1.0, {});
}

TEST(Crossings, PlainMeshJudgesOnlyPairsThreeEdgesApart) {
    for (const auto& [links, expected] : {std::pair{1, 0}, std::pair{2, 1}, std::pair{3, 2}}) {
        Points x;
        const Model m = needleThroughTriangle(links, x);
        EXPECT_EQ(countCrossings(m, x, {}).selfEdges, expected) << links << " links";
        EXPECT_EQ(bruteSelfCount(m, x), expected) << links << " links";
    }
}

// ---------------------------------------------------------------------------------------------
// Exact ties: the plane z = x / 4 + y / 8 + 1 / 2 through a triangle 8 km wide, and an edge PQ
// with P = (1, 1, pz) and Q = (1, 1, 3) above the plane, in a triangle PQR of its own (no vertex
// shared: every pair is far apart) with R = (2, 1, 9 / 8) on the plane. Every coordinate is a
// short binary fraction. With pz = 7 / 8, P is on the plane: its orientation against the big
// triangle is exactly 0, so PQ only touches it. One double step below (pz = 7 / 8 - 2^-53) PQ
// crosses it at (1, 1), and PR and QR still only touch it at R. That orientation is about 1e-8
// among products of 1e10, below what a long double evaluation can be sure of alone.

Model tieMesh(double pz, Points& x) {
    x.resize(3, 6);
    x.col(0) = Vec3(-4096, -4096, -4096.0 / 4 - 4096.0 / 8 + 0.5);
    x.col(1) = Vec3(4096, -4096, 4096.0 / 4 - 4096.0 / 8 + 0.5);
    x.col(2) = Vec3(0, 4096, 4096.0 / 8 + 0.5);
    x.col(3) = Vec3(1, 1, pz);       // P
    x.col(4) = Vec3(1, 1, 3);        // Q
    x.col(5) = Vec3(2, 1, 1.125);    // R, on the plane
    return Model::fromMesh(x, {{0, 1, 2}, {3, 4, 5}}, 1.0, {});
}

TEST(Crossings, AnEndOnTheTrianglesPlaneTouchesAndOneStepThroughCrosses) {
    Points x;
    EXPECT_EQ(countCrossings(tieMesh(0.875, x), x, {}).selfEdges, 0);
    EXPECT_EQ(countCrossings(tieMesh(std::nextafter(0.875, 0.0), x), x, {}).selfEdges, 1);
    EXPECT_EQ(countCrossings(tieMesh(std::nextafter(0.875, 1.0), x), x, {}).selfEdges, 0);
    // Seen from the other side (the whole scene mirrored in z, exactly): the same answers.
    for (const double pz : {0.875, std::nextafter(0.875, 0.0)}) {
        const Model m = tieMesh(pz, x);
        x.row(2) *= -1;
        EXPECT_EQ(countCrossings(m, x, {}).selfEdges, pz == 0.875 ? 0 : 1);
    }
}

// The segment PQ on the big triangle's plane, through its interior: coplanar, no crossing.
TEST(Crossings, AnEdgeLyingInTheTrianglesPlaneDoesNotCross) {
    Points x;
    const Model m = tieMesh(0.875, x);
    x.col(4) = Vec3(-1, 3, -0.25 + 0.375 + 0.5);  // (-1, 3) on the plane as well
    x.col(5) = Vec3(1, 1, 5);
    EXPECT_EQ(countCrossings(m, x, {}).selfEdges, 0);
}

// ---------------------------------------------------------------------------------------------
// The pole: a capsule of radius 3 cm around the axis x = z = 0, y from -1 to 1.

Model triangle(const Vec3& p, const Vec3& q, const Vec3& r, Points& x) {
    x.resize(3, 3);
    x << p, q, r;
    return Model::fromMesh(x, {{0, 1, 2}}, 0.01, {});
}

const CrossingScene::Capsule kPole{Vec3(0, -1, 0), Vec3(0, 1, 0), 0.03};

int poleEdges(const Vec3& p, const Vec3& q, const Vec3& r, const CrossingScene::Capsule& pole = kPole) {
    Points x;
    const Model m = triangle(p, q, r, x);
    CrossingScene scene;
    scene.capsules = {pole};
    return countCrossings(m, x, scene).poleEdges;
}

// The edge from (-0.05, 0, d) to (0.05, 0, d): its ends are 5 cm or more off the axis, its
// middle d. The third corner (0, 0, 0.5): the other two edges stay 5 cm or more away.
TEST(Crossings, AnEdgeWhoseMiddlePassesThroughThePoleCounts) {
    const Vec3 r(0, 0, 0.5);
    EXPECT_EQ(poleEdges(Vec3(-0.05, 0, 0.01), Vec3(0.05, 0, 0.01), r), 1);
    EXPECT_EQ(poleEdges(Vec3(-0.05, 0, 0.031), Vec3(0.05, 0, 0.031), r), 0);  // 1 mm outside
    // A ball (the axis a point) at the origin, the same radius.
    const CrossingScene::Capsule ball{Vec3::Zero(), Vec3::Zero(), 0.03};
    EXPECT_EQ(poleEdges(Vec3(-0.05, 0, 0.01), Vec3(0.05, 0, 0.01), r, ball), 1);
    EXPECT_EQ(poleEdges(Vec3(-0.05, 0, 0.031), Vec3(0.05, 0, 0.031), r, ball), 0);
}

TEST(Crossings, PoleDistanceHoldsForParallelEdgesAndPastTheAxisEnds) {
    // Parallel to the axis and longer than it, 2 cm off (inside) or 4 cm off (outside).
    EXPECT_EQ(poleEdges(Vec3(0.02, -2, 0), Vec3(0.02, 2, 0), Vec3(1, 0, 0)), 1);
    EXPECT_EQ(poleEdges(Vec3(0.04, -2, 0), Vec3(0.04, 2, 0), Vec3(1, 0, 0)), 0);
    // Across the axis 2 cm past its upper end (inside the cap), then 4 cm past it.
    EXPECT_EQ(poleEdges(Vec3(-0.5, 1.02, 0), Vec3(0.5, 1.02, 0), Vec3(0, 1.5, 0)), 1);
    EXPECT_EQ(poleEdges(Vec3(-0.5, 1.04, 0), Vec3(0.5, 1.04, 0), Vec3(0, 1.5, 0)), 0);
}

// The flag on a pole along its first column: every edge with an end on column 0 is on the axis
// (16 vertical, 17 horizontal, one diagonal per cell of the first column: 49); column 1 is 10 cm
// away. Skipped particles take their edges out of the count.
TEST(Crossings, SkippedParticlesEdgesAreNotCountedAgainstThePole) {
    const Model m = flag();
    CrossingScene scene;
    scene.capsules.push_back({Vec3(0, 0.5, 0), Vec3(0, -2, 0), 0.03});
    scene.grounds.push_back({Vec3(0, -1.05, 0), Vec3::UnitY()});
    const Points x = flat();
    EXPECT_EQ(countCrossings(m, x, scene).poleEdges, 49);
    std::vector<std::uint8_t> pins(17 * 17, 0);
    EXPECT_EQ(countCrossings(m, x, scene, &pins).poleEdges, 49);
    pins[0] = pins[16 * 17] = 1;  // the first column's top and bottom
    int pinned = 0;
    for (const auto& [p, q] : uniqueEdges(m)) pinned += pins[p] || pins[q];
    EXPECT_EQ(countCrossings(m, x, scene, &pins).poleEdges, 49 - pinned);
    for (int r = 0; r < 17; ++r) pins[r * 17] = 1;
    const CrossingCounts all = countCrossings(m, x, scene, &pins);
    EXPECT_EQ(all.poleEdges, 0);
    EXPECT_EQ(all.groundParticles, 6 * 17);  // skip is for the pole alone
}

// ---------------------------------------------------------------------------------------------
// The body and the ground.

// The box of half size 10 cm at the origin; an edge from (0.15, 0.04, z) to (0.04, 0.15, z) past
// its vertical corner edge x = y = 0.1: both ends outside, its middle (0.095, 0.095, z) inside
// when |z| < 0.1. Turned and moved together with the box, it counts the same.
int bodyEdges(const Vec3& p, const Vec3& q, const Mat3& turn = Mat3::Identity(), const Vec3& shift = Vec3::Zero()) {
    Points x;
    const Model m = triangle(turn * p + shift, turn * q + shift, turn * Vec3(1, 1, 1) + shift, x);
    CrossingScene scene;
    CrossingScene::Box box;
    box.center = shift;
    box.rotation = turn;
    box.halfExtents = Vec3::Constant(0.1);
    scene.boxes.push_back(box);
    return countCrossings(m, x, scene).bodyEdges;
}

TEST(Crossings, AnEdgeThroughABoxCornerCounts) {
    const Mat3 turn = Eigen::AngleAxisd(1.1, Vec3(-2, 1, 4).normalized()).toRotationMatrix();
    const Vec3 shift(2, -0.5, 4);
    for (const bool moved : {false, true}) {
        const Mat3 r = moved ? turn : Mat3::Identity();
        const Vec3 s = moved ? shift : Vec3::Zero();
        EXPECT_EQ(bodyEdges(Vec3(0.15, 0.04, 0.095), Vec3(0.04, 0.15, 0.095), r, s), 1) << moved;
        EXPECT_EQ(bodyEdges(Vec3(0.15, 0.04, 0.105), Vec3(0.04, 0.15, 0.105), r, s), 0) << moved;  // above the top
        EXPECT_EQ(bodyEdges(Vec3(0.16, 0.05, 0), Vec3(0.05, 0.16, 0), r, s), 0) << moved;  // x + y = 0.21
        // Wholly inside: that edge, and the two from its ends to the far corner.
        EXPECT_EQ(bodyEdges(Vec3(-0.05, 0, 0), Vec3(0.05, 0, 0), r, s), 3) << moved;
    }
    // Along a face (y = 0.1 exactly): touching, not inside.
    EXPECT_EQ(bodyEdges(Vec3(-0.5, 0.1, 0), Vec3(0.5, 0.1, 0)), 0);
}

// Rows 11..16 of the flag (y = -1.1 .. -1.6) are below y = -1.05; column 0 is left of x = 0.05.
TEST(Crossings, ParticlesBelowAGroundPlaneAreCountedOnce) {
    const Model m = flag();
    CrossingScene scene;
    scene.grounds.push_back({Vec3(0, -1.05, 0), Vec3(0, 2, 0)});  // the normal need not be unit
    EXPECT_EQ(countCrossings(m, flat(), scene).groundParticles, 6 * 17);
    scene.grounds.push_back({Vec3(0.05, 0, 0), Vec3(1, 0, 0)});
    EXPECT_EQ(countCrossings(m, flat(), scene).groundParticles, 6 * 17 + 11);
}

TEST(Crossings, PositionsOfTheWrongSizeAreRefused) {
    const Model m = flag();
    EXPECT_THROW(countCrossings(m, flat(9), {}), std::invalid_argument);
    const std::vector<std::uint8_t> skip(5, 0);
    EXPECT_THROW(countCrossings(m, flat(), {}, &skip), std::invalid_argument);
}

// A 65 x 65 flag, flat: nothing crosses (its cost is what the broad phase is for).
TEST(Crossings, LargeFlatFlagHasNone) {
    EXPECT_EQ(countCrossings(flag(65), flat(65), {}).total(), 0);
}
