#include <gtest/gtest.h>

#include <stdexcept>
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

// The anti-stretch pass's groups, checked by brute force: every spring exactly once, each group
// in spring order, and no particle in two of the blocks (the groups before the seam), which the
// pass runs at once on that promise.
void expectPassGroups(const Model& m, int blocks, const char* what) {
    ASSERT_EQ(m.passBlocks(), blocks) << what;
    ASSERT_EQ(m.passSprings().size(), m.springs().size()) << what;
    ASSERT_EQ(m.passGroupStart().back(), m.springCount()) << what;
    // Each group is a subsequence of springs(), and together they are all of it.
    std::vector<int> used(m.springCount(), 0);
    for (int g = 0; g <= blocks; ++g) {
        Index from = 0;
        for (Index k = m.passGroupStart()[g]; k < m.passGroupStart()[g + 1]; ++k) {
            const PassSpring& s = m.passSprings()[k];
            while (from < m.springCount() && !(m.springs()[from].i == s.i && m.springs()[from].j == s.j &&
                                               m.springs()[from].rest == s.rest))
                ++from;
            ASSERT_LT(from, m.springCount()) << what << ": group " << g << " is not in spring order at " << k;
            ++used[from++];
        }
    }
    for (Index s = 0; s < m.springCount(); ++s) EXPECT_EQ(used[s], 1) << what << ": spring " << s;
    std::vector<int> owner(m.particleCount(), -1);
    for (int g = 0; g < blocks; ++g)
        for (Index k = m.passGroupStart()[g]; k < m.passGroupStart()[g + 1]; ++k)
            for (const Index p : {m.passSprings()[k].i, m.passSprings()[k].j}) {
                EXPECT_TRUE(owner[p] == -1 || owner[p] == g) << what << ": particle " << p << " in blocks "
                                                             << owner[p] << " and " << g;
                owner[p] = g;
            }
}

TEST(Model, PassGroupsCoverEverySpringOnceAndBlocksShareNoParticle) {
    GridDesc g;
    g.nx = g.ny = 129;  // 16,641 particles: four blocks of about 32 rows
    const Model grid = Model::fromGrid(g);
    expectPassGroups(grid, 4, "129x129 grid");
    // The seam: the springs across the three cuts (structural, two shear and two bend springs
    // per column and cut, give or take the edges), a few percent of the springs.
    const Index seam = grid.passGroupStart()[5] - grid.passGroupStart()[4];
    EXPECT_GT(seam, 3 * 129 * 4);
    EXPECT_LT(seam, grid.springCount() / 20);
    g.nx = g.ny = 33;
    expectPassGroups(Model::fromGrid(g), 1, "33x33 grid");
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
