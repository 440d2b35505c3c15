// The fast kangcho steps (stencil layout for grids, per-particle gather for any mesh) against the
// straightforward reference: same iterates within rounding, on random states with pins, drag and
// external forces; 1 and 2 threads bit-identical.

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "cloth/presets.h"
#include "cloth/solver.h"
#include "cloth/solver_config.h"

using namespace cloth;

namespace {

struct FastCase {
    Model model;
    State state;
    std::vector<Pin> pins;
    Points external;
};

FastCase randomCase(bool grid, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Scalar> jitter(-0.02, 0.02), vel(-1, 1), force(-0.05, 0.05);
    Model model = [&] {
        GridDesc g;
        g.nx = 13;
        g.ny = 9;
        g.stiffness = {5e3, 1e3, 50};
        Model m = Model::fromGrid(g);
        if (grid) return m;
        // The same surface as an indexed mesh: edges and bends from triangles (a different
        // spring set, general adjacency).
        return Model::fromMesh(m.restPositions(), m.triangles(), 0.3, g.stiffness);
    }();
    State state = State::atRest(model);
    Points external(3, model.particleCount());
    for (Index i = 0; i < model.particleCount(); ++i)
        for (int a = 0; a < 3; ++a) {
            state.x(a, i) += jitter(rng);
            state.v(a, i) = vel(rng);
            external(a, i) = force(rng);
        }
    std::vector<Pin> pins;
    for (Index p : {0, 5, 12}) pins.push_back({p, state.x.col(p) + Vec3(0.01, -0.02, 0.03), Vec3(0.3, 0, -0.1)});
    return {std::move(model), std::move(state), std::move(pins), std::move(external)};
}

Points dvOf(const std::string& spec, const FastCase& c, const Environment& env) {
    SolverConfig config;
    std::string error;
    EXPECT_TRUE(parseSolverConfig(spec, config, &error)) << error;
    auto solver = makeSolver(config);
    State state = c.state;
    StepInput input;
    input.h = 1.0 / 120;
    input.pins = c.pins;
    input.externalForce = &c.external;
    EXPECT_EQ(solver->step(c.model, env, state, input).status, StepStatus::Ok) << spec;
    return solver->lastDv();
}

}  // namespace

TEST(FastStep, MatchesTheReferenceWithinRounding) {
    Environment env;
    env.drag = 0.3;
    for (bool grid : {true, false})
        for (int iterations : {0, 1, 4})
            for (const char* compression : {"on", "off"}) {
                const FastCase c = randomCase(grid, 17 + iterations);
                const std::string params =
                    ":iterations=" + std::to_string(iterations) + ",compression=" + compression;
                const Points ref = dvOf("kangcho" + params + ",impl=reference", c, env);
                for (const char* impl : {"fast", "gather"}) {
                    const std::string spec = "kangcho" + params + ",impl=" + impl;
                    const Points fast = dvOf(spec, c, env);
                    const Points single = dvOf(spec + ",precision=float", c, env);
                    const std::string what = std::string(grid ? "grid " : "mesh ") + spec;
                    EXPECT_LT((fast - ref).norm(), 1e-12 * ref.norm()) << what;
                    // float: eps 6e-8 times the conditioning of W_ii, which compression=off makes
                    // poor (J is indefinite under compression). The worst case here is 1.01e-4
                    // without fused multiply-adds (-ffp-contract=off), 0.9e-4 with them.
                    EXPECT_LT((single - ref).norm(), 3e-4 * ref.norm()) << what;
                    EXPECT_GT((single - ref).norm(), 0.0) << what << ": float should differ from double";
                }
            }
}

TEST(FastStep, OneAndTwoThreadsAreBitIdentical) {
    for (const char* precision : {"double,impl=fast", "float,impl=fast", "double,impl=gather", "float,impl=gather"}) {
        State results[2];
        int k = 0;
        for (int threads : {1, 2}) {
            HangingFlagDesc d;
            d.nx = d.ny = 33;
            HangingFlag flag = makeHangingFlag(d);
            SolverConfig config;
            parseSolverConfig("kangcho:threads=" + std::to_string(threads) + ",precision=" + precision, config,
                              nullptr);
            auto solver = makeSolver(config);
            StepInput input;
            input.h = 1.0 / 240;
            input.pins = flag.pins;
            for (int s = 0; s < 200; ++s) solver->step(flag.model, Environment{}, flag.state, input);
            results[k++] = flag.state;
        }
        EXPECT_EQ(std::memcmp(results[0].x.data(), results[1].x.data(), sizeof(Scalar) * results[0].x.size()), 0)
            << precision;
        EXPECT_EQ(std::memcmp(results[0].v.data(), results[1].v.data(), sizeof(Scalar) * results[0].v.size()), 0)
            << precision;
    }
}
