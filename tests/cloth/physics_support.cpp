#include "physics_support.h"

#include <gtest/gtest.h>

#include "cloth/solver_config.h"

namespace cloth::test {

std::unique_ptr<Solver> solverFor(const std::string& spec, const std::function<void(MultigridTuning&)>& tune) {
    SolverConfig config;
    std::string error;
    if (!parseSolverConfig(spec, config, &error)) {
        ADD_FAILURE() << "spec '" << spec << "': " << error;
        return nullptr;
    }
    if (tune) {
        MultigridSettings& s = config.get<MultigridSettings>();
        MultigridTuning t = settledTuning(s);
        tune(t);
        s.tuning = t;
    }
    auto solver = makeSolver(config, &error);
    if (!solver) ADD_FAILURE() << "spec '" << spec << "': " << error;
    return solver;
}

Vec3 randomVec(std::mt19937& rng, Scalar lo, Scalar hi) {
    std::uniform_real_distribution<Scalar> u(lo, hi);
    const Scalar a = u(rng), b = u(rng), c = u(rng);  // named: argument order is unspecified
    return Vec3(a, b, c);
}

Cloth deformedGrid(int nx, int ny, const Stiffness& k, Scalar jitter, Scalar speed, unsigned seed) {
    GridDesc g;
    g.nx = nx;
    g.ny = ny;
    g.width = 1.0;
    g.height = 0.8;
    g.stiffness = k;
    Cloth c{Model::fromGrid(g), {}};
    c.state = State::atRest(c.model);
    const Scalar spacing = g.width / (nx - 1);
    std::mt19937 rng(seed);
    for (Index i = 0; i < c.model.particleCount(); ++i) {
        c.state.x.col(i) += randomVec(rng, -jitter * spacing, jitter * spacing);
        c.state.v.col(i) = randomVec(rng, -speed, speed);
    }
    return c;
}

std::vector<Pin> movingPins(const Cloth& c, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<Pin> pins;
    for (int r = 0; r < c.model.gridNy(); ++r) {
        const Index p = r * c.model.gridNx();
        const Vec3 offset = randomVec(rng, -0.01, 0.01), velocity = randomVec(rng, -1, 1);
        pins.push_back({p, Vec3(c.state.x.col(p) + offset), velocity});
    }
    return pins;
}

Points randomPoints(int n, Scalar magnitude, unsigned seed) {
    std::mt19937 rng(seed);
    Points p(3, n);
    for (int i = 0; i < n; ++i) p.col(i) = randomVec(rng, -magnitude, magnitude);
    return p;
}

RigidFrame turningCarrier(double t) {
    RigidFrame c;
    c.position = Vec3(0, 0, 3 * t * t);
    c.linearVelocity = Vec3(0, 0, 6 * t);
    c.rotation = Eigen::AngleAxisd(0.8 * t, Vec3::UnitY());
    c.angularVelocity = Vec3(0, 0.8, 0);
    return c;
}

}  // namespace cloth::test
