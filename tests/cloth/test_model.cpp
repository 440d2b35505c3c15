#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "cloth/diagnostics.h"
#include "cloth/model.h"

using namespace cloth;

TEST(Model, GridSpringCountsAndMass) {
    GridDesc g;
    g.nx = 6;
    g.ny = 4;
    g.totalMass = 0.7;
    const Model m = Model::fromGrid(g);
    int count[3] = {};
    for (const Spring& s : m.springs()) ++count[int(s.kind)];
    EXPECT_EQ(count[0], 5 * 4 + 6 * 3);      // structural: grid edges
    EXPECT_EQ(count[1], 2 * 5 * 3);          // shear: two diagonals per quad
    EXPECT_EQ(count[2], 4 * 4 + 6 * 2);      // bend: skip-one along rows and columns
    EXPECT_EQ(m.triangles().size(), 2u * 5 * 3);
    EXPECT_NEAR(m.totalMass(), 0.7, 1e-12);
    for (const Spring& s : m.springs())
        EXPECT_NEAR(s.rest, (m.restPositions().col(s.j) - m.restPositions().col(s.i)).norm(), 1e-15);
}

TEST(Model, MeshSpringsFromEdgesAndBendsAcrossInteriorEdges) {
    // Two triangles sharing edge (1, 2): 5 edges, 1 interior edge -> 1 bend spring (0, 3).
    Points x(3, 4);
    x << 0, 1, 0, 1,  //
        0, 0, 1, 1,   //
        0, 0, 0, 0;
    const Model m = Model::fromMesh(x, {{0, 1, 2}, {2, 1, 3}}, 1.0, {10, 0, 2});
    int structural = 0, bend = 0;
    for (const Spring& s : m.springs()) {
        if (s.kind == SpringKind::Structural) ++structural;
        if (s.kind == SpringKind::Bend) {
            ++bend;
            EXPECT_EQ(s.i, 0);
            EXPECT_EQ(s.j, 3);
        }
    }
    EXPECT_EQ(structural, 5);
    EXPECT_EQ(bend, 1);
    EXPECT_NEAR(m.totalMass(), 1.0, 1e-12);
}

// The anti-stretch pass's colours, checked by brute force: every spring exactly once, and no two
// springs of a colour sharing a particle (the pass corrects a colour's springs in any order, and
// splits it among threads, on that promise).
void expectProperColouring(const Model& m, const char* what) {
    ASSERT_EQ(m.colouredSprings().size(), m.springs().size()) << what;
    ASSERT_EQ(m.colourStart().back(), m.springCount()) << what;
    auto key = [](const Spring& s) { return std::tuple(s.i, s.j, int(s.kind), s.k, s.rest); };
    std::vector<std::tuple<Index, Index, int, Scalar, Scalar>> a, b;
    for (const Spring& s : m.springs()) a.push_back(key(s));
    for (const Spring& s : m.colouredSprings()) b.push_back(key(s));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b) << what << ": the coloured springs are not the springs";
    for (std::size_t c = 0; c + 1 < m.colourStart().size(); ++c) {
        std::vector<int> seen(m.particleCount(), 0);
        for (Index k = m.colourStart()[c]; k < m.colourStart()[c + 1]; ++k) {
            const Spring& s = m.colouredSprings()[k];
            for (const Index p : {s.i, s.j})
                EXPECT_EQ(seen[p]++, 0) << what << ": particle " << p << " twice in colour " << c;
        }
    }
}

TEST(Model, SpringColoursCoverEverySpringOnceAndShareNoParticle) {
    GridDesc g;
    g.nx = 9;
    g.ny = 7;
    const Model grid = Model::fromGrid(g);
    expectProperColouring(grid, "9x7 grid");
    // Greedy in spring order gives a grid 12 colours (a particle has 12 springs, so no fewer).
    EXPECT_EQ(grid.colourStart().size() - 1, 12u);
    // A fan: one vertex in 8 triangles, so 8 structural springs meet there.
    Points x(3, 9);
    x.col(0) = Vec3::Zero();
    std::vector<Triangle> fan;
    for (int k = 0; k < 8; ++k) {
        x.col(k + 1) = Vec3(std::cos(k * M_PI / 4), std::sin(k * M_PI / 4), 0);
        fan.push_back({0, k + 1, (k + 1) % 8 + 1});
    }
    const Model mesh = Model::fromMesh(x, fan, 1.0, {10, 0, 2});
    expectProperColouring(mesh, "fan");
    EXPECT_GE(mesh.colourStart().size() - 1, 8u);
}

TEST(Model, BadInputNamesFieldAndValue) {
    GridDesc g;
    g.nx = 1;
    try {
        Model::fromGrid(g);
        FAIL() << "no error for nx = 1";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("nx = 1"), std::string::npos) << e.what();
    }
    g.nx = 5;
    g.totalMass = -1;
    EXPECT_THROW(Model::fromGrid(g), std::invalid_argument);
    Points x(3, 3);
    x << 0, 1, 2, 0, 0, 0, 0, 0, 0;  // collinear: a degenerate triangle
    EXPECT_THROW(Model::fromMesh(x, {{0, 1, 2}}, 1.0, {}), std::invalid_argument);
    x << 0, 1, 0, 0, 0, 1, 0, 0, 0;
    EXPECT_THROW(Model::fromMesh(x, {{0, 1, 5}}, 1.0, {}), std::invalid_argument);
}

TEST(Diagnostics, StrainAndEnergyOfAKnownState) {
    GridDesc g;
    g.nx = 3;
    g.ny = 2;
    g.width = 2;
    g.height = 1;
    g.stiffness = {100, 100, 0};
    const Model m = Model::fromGrid(g);
    State s = State::atRest(m);
    s.x.row(0) *= 1.1;  // stretch 10% along x
    s.v.setConstant(2.0);
    Environment env;
    env.gravity.setZero();
    const Diagnostics d = measure(m, env, s, true);
    EXPECT_NEAR(d.maxStretch, 0.1, 1e-12);
    EXPECT_NEAR(d.maxCompression, 0.0, 1e-15);
    EXPECT_NEAR(d.kinetic, 0.5 * m.totalMass() * 12.0, 1e-12);
    // Potential: 4 horizontal springs of rest 1 stretched by 0.1, plus the diagonals.
    Scalar expected = 4 * 0.5 * 100 * 0.01;
    const Scalar diagRest = std::sqrt(2.0), diagNow = std::sqrt(1.21 + 1.0);
    expected += 4 * 0.5 * 100 * (diagNow - diagRest) * (diagNow - diagRest);
    EXPECT_NEAR(d.potential, expected, 1e-12);
}
