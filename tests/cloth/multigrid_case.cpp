#include "multigrid_case.h"

#include <gtest/gtest.h>

#include <random>

#include "cloth/paper_step.h"
#include "solver_spec.h"

namespace cloth::test {

// A stiff flag (k 1e4, 0.3 kg) on a grid or the same surface as a mesh, in a deformed and moving
// state like a flag's (stretched 5% along its length, a wave across it, and a random ripple of
// `rough` times the spacing), its column 0 pinned to targets that move.
Case stiffCase(int nx, int ny, bool mesh, unsigned seed, Scalar rough) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Scalar> jitter(-rough, rough), vel(-2, 2), force(-0.01, 0.01);
    GridDesc g;
    g.nx = nx;
    g.ny = ny;
    g.stiffness = {1e4, 1e4, 1e3};
    Model grid = Model::fromGrid(g);
    Model model = mesh ? Model::fromMesh(grid.restPositions(), grid.triangles(), 0.3, g.stiffness) : grid;
    State state = State::atRest(model);
    const Scalar spacing = g.width / (nx - 1);
    Points external(3, model.particleCount());
    for (Index i = 0; i < model.particleCount(); ++i) {
        const Vec3 r = model.restPositions().col(i);
        state.x(0, i) = 1.05 * r.x();
        state.x(2, i) = 0.1 * std::sin(4 * r.x() + 2 * r.y());
        for (int a = 0; a < 3; ++a) {
            state.x(a, i) += spacing * jitter(rng);
            state.v(a, i) = vel(rng);
            external(a, i) = force(rng);
        }
    }
    std::vector<Pin> pins;
    for (int r = 0; r < ny; ++r) {
        const Index p = r * nx;  // the grid's and the mesh's vertex order are the same
        pins.push_back({p, state.x.col(p) + Vec3(0.002, -0.001, 0.003), Vec3(1, 0, 0)});
    }
    return {std::move(model), std::move(state), std::move(pins), std::move(external)};
}

StepInput inputOf(const Case& c, Scalar h) {
    StepInput in;
    in.h = h;
    in.pins = c.pins;
    in.externalForce = &c.external;
    return in;
}

// W of the reference path with pinned rows and columns zeroed: the matrix of the free unknowns,
// which is what multigrid's level 0 holds.
Eigen::MatrixXd referenceFreeMatrix(const Case& c, const LinearSystem& sys) {
    Eigen::MatrixXd W = Eigen::MatrixXd(assembleMatrix(c.model, sys));
    for (Index i = 0; i < c.model.particleCount(); ++i)
        if (sys.pinned[i]) {
            W.middleRows(3 * i, 3).setZero();
            W.middleCols(3 * i, 3).setZero();
        }
    return W;
}

// Settings with their settled tuning changed by `tune`.
MultigridSettings tuned(MultigridSettings s, const Tune& tune) {
    MultigridTuning t = settledTuning(s);
    tune(t);
    s.tuning = t;
    return s;
}

Points stepDv(const std::string& spec, const Case& c, const Environment& env, const Tune& tune) {
    auto solver = tune ? solverFor(spec, tune) : solverOf(spec);
    State state = c.state;
    const StepResult r = solver->step(c.model, env, state, inputOf(c));
    EXPECT_EQ(r.status, StepStatus::Ok) << spec;
    return solver->lastDv();
}

}  // namespace cloth::test
