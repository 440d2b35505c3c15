// Physics of the cloth library against computations written here, independently of the library:
//   PhysicsAir          the per-triangle air force formula of air.h, evaluated by hand
//   PhysicsCollision    distances and normals of planes, capsules and boxes from their geometry;
//                       projection onto the surface and Coulomb friction written out
//   PhysicsStretchLimit Provot's correction for one spring by hand; the promises of the stretch
//                       limit (constraints.h: limit reached, pins still, momentum and centroid kept)
//   PhysicsTethers      long-range attachments against each particle's nearest pin at rest,
//                       found here by brute force; the move is radial and v changes by dx / h
//   PhysicsChebyshev    Wang's Chebyshev recurrence run on the dense matrix with dense 3x3
//                       block Jacobi
//   PhysicsPins         the full 3n x 3n backward Euler system (springs, eq. 17, drag, damping,
//                       external force) built here and solved densely with the pins eliminated
//   Golden*             FNV-1a hashes of a fixed 60-step run, per solver, equal for 1 and 2
//                       threads, against tests/cloth/golden_hashes.txt
// Solvers are configured only through spec strings (parseSolverConfig + makeSolver).

#include <functional>
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cloth/air.h"
#include "cloth/collision.h"
#include "cloth/presets.h"
#include "cloth/multigrid_settings.h"
#include "cloth/solver.h"
#include "cloth/constraints.h"
#include "cloth/system.h"
#include "cloth/thread_pool.h"

#ifndef FLAGSIM_TEST_DATA_DIR
#error "FLAGSIM_TEST_DATA_DIR must name the directory of golden_hashes.txt (tests/CMakeLists.txt)"
#endif

using namespace cloth;

namespace {

// ---------------------------------------------------------------------------------------------
// Shared helpers

// The solver of `spec`; a multigrid one with its settled tuning changed by `tune`, where given.
std::unique_ptr<Solver> solverFor(const std::string& spec, const std::function<void(MultigridTuning&)>& tune = nullptr) {
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

Eigen::VectorXd flat(const Points& p) { return Eigen::Map<const Eigen::VectorXd>(p.data(), p.size()); }

Scalar relativeError(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
    return (got - want).norm() / want.norm();
}

// A grid cloth (column 0 on the pole side) in a random deformed, moving state: positions
// jittered by `jitter` times the spacing (so some springs are stretched and some compressed),
// velocities uniform in [-speed, speed].
struct Cloth {
    Model model;
    State state;
};
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

// Pins on column 0 whose targets are off the current positions and move: the general case.
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

// ---------------------------------------------------------------------------------------------
// Air

// The force on one triangle as air.h documents it: area A, unit normal n oriented with the flow
// (w . n >= 0), relative air velocity w = wind - mean corner velocity, s = |w|, wn = w . n,
// c_X = 1/2 rho A C_X; drag c_d s wn n, skin friction c_f s (w - wn n), lift
// c_l (wn s n - (wn^2 / s) w).
Vec3 documentedAirForce(const Vec3 (&x)[3], const Vec3 (&v)[3], const AirParams& air) {
    const Vec3 cross = (x[1] - x[0]).cross(x[2] - x[0]);
    const Scalar area = cross.norm() / 2;
    const Vec3 w = air.wind - (v[0] + v[1] + v[2]) / 3;
    const Scalar s = w.norm();
    const Vec3 n = (w.dot(cross) >= 0 ? 1.0 : -1.0) * cross.normalized();
    const Scalar wn = w.dot(n);
    const Scalar halfRhoA = 0.5 * air.density * area;
    const Vec3 drag = halfRhoA * air.dragCoefficient * s * wn * n;
    const Vec3 friction = halfRhoA * air.frictionCoefficient * s * (w - wn * n);
    const Vec3 lift = halfRhoA * air.liftCoefficient * (wn * s * n - (wn * wn / s) * w);
    return drag + friction + lift;
}

// Every corner gets a third of each of its triangles' documented force.
Points documentedAirForces(const Model& model, const State& state, const AirParams& air) {
    Points f = Points::Zero(3, model.particleCount());
    for (const Triangle& t : model.triangles()) {
        const Vec3 x[3] = {state.x.col(t[0]), state.x.col(t[1]), state.x.col(t[2])};
        const Vec3 v[3] = {state.v.col(t[0]), state.v.col(t[1]), state.v.col(t[2])};
        const Vec3 third = documentedAirForce(x, v, air) / 3;
        for (const Index p : t) f.col(p) += third;
    }
    return f;
}

// One triangle, and two sharing an edge (a corner's force then sums two triangles).
std::vector<Model> airModels() {
    Points rest(3, 4);
    rest << 0, 1, 0, 1.2,  //
        0, 0, 1, 0.9,      //
        0, 0, 0, 0.3;
    return {Model::fromMesh(rest.leftCols(3), {{0, 1, 2}}, 0.01, {10, 10, 1}),
            Model::fromMesh(rest, {{0, 1, 2}, {1, 3, 2}}, 0.02, {10, 10, 1})};
}

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

// ---------------------------------------------------------------------------------------------
// Dense linear algebra for the solver tests

// The block diagonal (3x3 blocks) of a dense matrix, inverted block by block.
Eigen::MatrixXd blockDiagonalInverse(const Eigen::MatrixXd& W) {
    Eigen::MatrixXd inv = Eigen::MatrixXd::Zero(W.rows(), W.cols());
    for (Eigen::Index b = 0; b < W.rows(); b += 3) inv.block(b, b, 3, 3) = Mat3(W.block(b, b, 3, 3)).inverse();
    return inv;
}

Eigen::MatrixXd blockDiagonal(const Eigen::MatrixXd& W) {
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(W.rows(), W.cols());
    for (Eigen::Index b = 0; b < W.rows(); b += 3) d.block(b, b, 3, 3) = W.block(b, b, 3, 3);
    return d;
}

// Adds the 3x3 block B at block position (i, j).
void addBlock(Eigen::MatrixXd& A, Index i, Index j, const Mat3& B) { A.block<3, 3>(3 * i, 3 * j) += B; }

// ---------------------------------------------------------------------------------------------
// Golden hashes

// 64-bit FNV-1a over raw bytes, continuing from `hash`.
std::uint64_t fnv1a(const void* data, std::size_t bytes, std::uint64_t hash = 0xcbf29ce484222325ull) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) {
        hash ^= p[k];
        hash *= 0x100000001b3ull;
    }
    return hash;
}

std::uint64_t stateHash(const State& s) {
    const std::uint64_t hx = fnv1a(s.x.data(), sizeof(Scalar) * s.x.size());
    return fnv1a(s.v.data(), sizeof(Scalar) * s.v.size(), hx);
}

std::string hex(std::uint64_t value) {
    std::ostringstream s;
    s << std::hex << std::setw(16) << std::setfill('0') << value;
    return s.str();
}

// The golden file: "<spec> <hex hash>" per line; '#' starts a comment line.
std::map<std::string, std::string> readGoldenHashes(const std::string& path) {
    std::map<std::string, std::string> golden;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string spec, hash;
        if (!(fields >> spec >> hash) || spec[0] == '#') continue;
        golden[spec] = hash;
    }
    return golden;
}

// The fixed scenario: a 17 x 17 hanging flag whose pole moves along a polynomial path (no libm
// calls, so nothing here depends on the C library's rounding), explicit air on a side wind,
// light drag; 60 steps of 1/240 s.
State runGoldenScenario(const std::string& spec, const std::function<void(MultigridTuning&)>& tune) {
    HangingFlagDesc d;
    d.nx = d.ny = 17;
    HangingFlag flag = makeHangingFlag(d);
    auto solver = solverFor(spec, tune);
    if (!solver) return flag.state;
    Environment env;
    env.drag = 0.05;
    AirParams air;
    air.wind = Vec3(6, 0, 1.5);
    StepInput input;
    input.h = 1.0 / 240;
    Points external;
    for (int step = 1; step <= 60; ++step) {
        const Scalar t = step * input.h;
        const Vec3 offset(0.4 * t, 0.2 * t - 1.5 * t * t, 0.3 * t * t);
        const Vec3 velocity(0.4, 0.2 - 3 * t, 0.6 * t);
        const std::vector<Pin> pins = pinColumn(flag.model, offset, velocity);
        external.setZero(3, flag.model.particleCount());
        addAirForces(flag.model, flag.state, air, external);
        input.pins = pins;
        input.externalForce = &external;
        const StepResult r = solver->step(flag.model, env, flag.state, input);
        if (r.status != StepStatus::Ok) {
            ADD_FAILURE() << spec << ": step " << step << " failed: " << toString(r.status);
            break;
        }
    }
    return flag.state;
}

// Runs `base` with `threads` threads and compares the final state's hash with the golden value
// recorded for `base` (the same for every thread count).
// `base`: the spec, and the label of the hash; with a tuning, the label is the spec, a slash and
// a name for the tuning.
void expectGoldenHash(const std::string& base, int threads, const std::function<void(MultigridTuning&)>& tune = nullptr) {
    const std::string specOnly = base.substr(0, base.find('/'));
    const std::string spec = specOnly + (specOnly.find(':') == std::string::npos ? ":" : ",") +
                             "threads=" + std::to_string(threads);
    const std::string path = std::string(FLAGSIM_TEST_DATA_DIR) + "/golden_hashes.txt";
    const std::string computed = hex(stateHash(runGoldenScenario(spec, tune)));
    const auto golden = readGoldenHashes(path);
    const auto it = golden.find(base);
    ASSERT_TRUE(it != golden.end()) << "no golden hash for '" << base << "' in " << path
                                   << "; computed with " << spec << ": " << computed
                                   << " (add the line: " << base << " " << computed << ")";
    EXPECT_EQ(computed, it->second)
        << spec << ": final state hash " << computed << " differs from the golden " << it->second
        << " in " << path << ". If the change is intended, update that line to: " << base << " "
        << computed;
}

}  // namespace

// =============================================================================================
// 1. Air

TEST(PhysicsAir, ForcesEqualTheDocumentedPerTriangleFormula) {
    struct Coefficients {
        const char* name;
        Scalar drag, lift, friction;
    };
    // Each term alone (a wrong term is named by the failure), then all together.
    const Coefficients sets[] = {
        {"drag", 1.1, 0, 0}, {"lift", 0, 0.7, 0}, {"friction", 0, 0, 0.3}, {"all", 1.1, 0.7, 0.3}};
    for (const Coefficients& c : sets) {
        Scalar worst = 0;  // the largest relative error over the random cases, and where
        std::string worstCase;
        for (const Model& model : airModels()) {
            const int n = model.particleCount();
            for (unsigned seed = 1; seed <= 20; ++seed) {
                std::mt19937 rng(seed);
                State state = State::atRest(model);
                for (Index i = 0; i < n; ++i) {
                    state.x.col(i) += randomVec(rng, -0.3, 0.3);
                    state.v.col(i) = randomVec(rng, -3, 3);
                }
                AirParams air;
                air.wind = randomVec(rng, -10, 10);
                air.density = 1.25;
                air.dragCoefficient = c.drag;
                air.liftCoefficient = c.lift;
                air.frictionCoefficient = c.friction;
                const Points before = randomPoints(n, 0.01, seed);  // addAirForces adds to f
                Points f = before;
                addAirForces(model, state, air, f);
                const Points expected = documentedAirForces(model, state, air);
                const Scalar error = relativeError(flat(f - before), flat(expected));
                if (error > worst) {
                    worst = error;
                    std::ostringstream where;
                    where << model.triangles().size() << " triangle(s), seed " << seed << ": library force on particle 0 "
                          << (f - before).col(0).transpose() << ", formula of air.h " << expected.col(0).transpose();
                    worstCase = where.str();
                }
            }
        }
        EXPECT_LE(worst, 1e-12) << c.name << " coefficients, worst case " << worstCase;
    }
}

TEST(PhysicsAir, TwoThreadsAndTheForcesAloneGiveTheBitsOfOne) {
    // The forces and their velocity Jacobian on a moving 33 x 33 flag; the formula itself is
    // checked above, on one thread.
    HangingFlag flag = makeHangingFlag(HangingFlagDesc{});
    std::mt19937 rng(4);
    for (Index i = 0; i < flag.model.particleCount(); ++i) {
        flag.state.x.col(i) += randomVec(rng, -0.01, 0.01);
        flag.state.v.col(i) = randomVec(rng, -3, 3);
    }
    AirParams air;
    air.wind = Vec3(6, 1, -2);
    const Points start = randomPoints(flag.model.particleCount(), 0.01, 4);
    Points one = start, split = start;
    std::vector<Mat3> jOne, jSplit;
    ThreadPool two(2);
    addAirForces(flag.model, flag.state, air, one, &jOne);
    addAirForces(flag.model, flag.state, air, split, &jSplit, &two);
    EXPECT_GT((one - start).norm(), 1e-3) << "the air should push the flag";
    EXPECT_TRUE(one == split) << "max |df| " << (one - split).cwiseAbs().maxCoeff();
    for (std::size_t i = 0; i < jOne.size(); ++i) ASSERT_TRUE(jOne[i] == jSplit[i]) << "df/dv of particle " << i;
    // Without the Jacobian, the bits of the forces with it, on one thread and on two.
    Points alone = start, alone2 = start;
    addAirForces(flag.model, flag.state, air, alone);
    addAirForces(flag.model, flag.state, air, alone2, nullptr, &two);
    EXPECT_TRUE(alone == one) << "max |df| " << (alone - one).cwiseAbs().maxCoeff();
    EXPECT_TRUE(alone2 == one) << "max |df| " << (alone2 - one).cwiseAbs().maxCoeff();
}

TEST(PhysicsAir, NoForceWhenTheAirMovesWithTheCloth) {
    for (const Model& model : airModels()) {
        std::mt19937 rng(7);
        State state = State::atRest(model);
        AirParams air;
        air.wind = Vec3(7.3, -0.1, 2.9);
        for (Index i = 0; i < model.particleCount(); ++i) {
            state.x.col(i) += randomVec(rng, -0.3, 0.3);
            state.v.col(i) = air.wind;  // every particle moves with the air
        }
        Points f = Points::Zero(3, model.particleCount());
        std::vector<Mat3> dfdv;
        addAirForces(model, state, air, f, &dfdv);
        EXPECT_LE(f.norm(), 1e-12) << "force on cloth at rest relative to the air:\n" << f;
        // The force is quadratic in w, so its velocity derivative vanishes at w = 0 as well.
        for (std::size_t i = 0; i < dfdv.size(); ++i)
            EXPECT_LE(dfdv[i].norm(), 1e-12) << "df/dv of particle " << i << ":\n" << dfdv[i];
    }
}

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

static StepInput stepInput(Scalar h, const std::vector<Pin>& pins, const Points* external) {
    StepInput input;
    input.h = h;
    input.pins = pins;
    input.externalForce = external;
    return input;
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

// =============================================================================================
// 4. Chebyshev

TEST(PhysicsChebyshev, IteratesEqualTheRecurrenceOnTheDenseSystem) {
    const Cloth c = deformedGrid(6, 5, {3e3, 3e3, 300}, 0.05, 0.5, 21);
    const std::vector<Pin> pins = movingPins(c, 22);
    const Points external = randomPoints(c.model.particleCount(), 0.02, 23);
    Environment env;
    env.drag = 0.3;
    const StepInput input = stepInput(1.0 / 60, pins, &external);
    LinearSystem sys;
    buildSystem({c.model, env, c.state, input, true}, sys);
    const Eigen::MatrixXd W(assembleMatrix(c.model, sys));
    const Eigen::VectorXd b = flat(sys.rhs);  // pinned rows of W are identity, b their dv
    const Eigen::MatrixXd Dinv = blockDiagonalInverse(W), offDiagonal = W - blockDiagonal(W);
    auto jacobi = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return Dinv * (b - offDiagonal * x); };

    const Scalar rho = 0.9;
    for (int K : {1, 2, 5}) {
        // Wang 2015: x(k+1) = w(k+1) (J(x(k)) - x(k-1)) + x(k-1), w1 = 1, w2 = 2 / (2 - rho^2),
        // w(k+1) = 4 / (4 - rho^2 w(k)), from x(0) = x(-1) = W_ii^-1 b_i.
        Eigen::VectorXd previous = Dinv * b, current = previous;
        Scalar w = 1;
        for (int k = 1; k <= K; ++k) {
            w = k == 1 ? 1 : k == 2 ? 2 / (2 - rho * rho) : 4 / (4 - rho * rho * w);
            Eigen::VectorXd next = w * (jacobi(current) - previous) + previous;
            previous = current;
            current = next;
        }
        auto solver = solverFor("chebyshev:iterations=" + std::to_string(K) + ",rho=0.9");
        ASSERT_TRUE(solver);
        State state = c.state;
        ASSERT_EQ(solver->step(c.model, env, state, input).status, StepStatus::Ok);
        EXPECT_LE(relativeError(flat(solver->lastDv()), current), 1e-10)
            << "chebyshev:iterations=" << K << ",rho=0.9: lastDv() differs from the dense recurrence";
    }
}

// =============================================================================================
// 5. Pins and drag: the full backward Euler system

TEST(PhysicsPins, ExactStepSolvesTheFullBackwardEulerSystemWithPinsDragAndForces) {
    const Cloth c = deformedGrid(5, 4, {1e3, 1e3, 100}, 0.15, 1.0, 31);
    const Model& model = c.model;
    const State& s = c.state;
    const int n = model.particleCount(), N = 3 * n;
    const std::vector<Pin> pins = movingPins(c, 32);
    const Points external = randomPoints(n, 0.05, 33);
    std::vector<Mat3> damping(n);  // symmetric positive semi-definite C_i
    for (Index i = 0; i < n; ++i) {
        const Mat3 B = randomPoints(3, 0.1, 100 + i);
        damping[i] = B * B.transpose();
    }
    Environment env;
    env.drag = 0.8;
    StepInput input = stepInput(1.0 / 120, pins, &external);
    input.damping = &damping;
    const Scalar h = input.h;

    // f(x, v) and its derivatives K = df/dx, D = df/dv, all written out here.
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N, N), K = M, D = M;
    Eigen::VectorXd f(N);
    for (Index i = 0; i < n; ++i) {
        const Scalar m = model.masses()[i];
        addBlock(M, i, i, m * Mat3::Identity());
        addBlock(D, i, i, -env.drag * m * Mat3::Identity() - damping[i]);  // C_i = -df_i/dv_i
        f.segment<3>(3 * i) = m * env.gravity - env.drag * m * s.v.col(i) + external.col(i);
    }
    int stretched = 0, compressed = 0;
    for (const Spring& sp : model.springs()) {
        const Vec3 d = s.x.col(sp.j) - s.x.col(sp.i);
        const Scalar L = d.norm();
        const Vec3 u = d / L;
        f.segment<3>(3 * sp.i) += sp.k * (L - sp.rest) * u;  // eq. 15
        f.segment<3>(3 * sp.j) -= sp.k * (L - sp.rest) * u;
        const Scalar r = std::min(sp.rest / L, Scalar(1));  // eq. 17: l0 := L under compression
        const Mat3 J = sp.k * ((1 - r) * Mat3::Identity() + r * u * u.transpose());  // eq. 16
        addBlock(K, sp.i, sp.j, J);
        addBlock(K, sp.j, sp.i, J);
        addBlock(K, sp.i, sp.i, -J);
        addBlock(K, sp.j, sp.j, -J);
        (L > sp.rest ? stretched : compressed) += 1;
    }
    ASSERT_GT(stretched, 5);
    ASSERT_GT(compressed, 5);  // eq. 17 is exercised

    // Linearized backward Euler: (M - h D - h^2 K) dv = h (f + h K v).
    const Eigen::MatrixXd A = M - h * D - h * h * K;
    const Eigen::VectorXd b = h * (f + h * K * flat(s.v));

    // Pinned dv lands the particle on its target: dv_p = (x_target - x_p) / h - v_p. Eliminate
    // those unknowns: A_FF dv_F = b_F - A_FP dv_P.
    std::vector<bool> isPinned(n, false);
    Eigen::VectorXd dv = Eigen::VectorXd::Zero(N);
    for (const Pin& p : pins) {
        isPinned[p.particle] = true;
        dv.segment<3>(3 * p.particle) = (p.x - s.x.col(p.particle)) / h - s.v.col(p.particle);
    }
    std::vector<Eigen::Index> freeRows, pinRows;
    for (Index i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) (isPinned[i] ? pinRows : freeRows).push_back(3 * i + a);
    const Eigen::MatrixXd Aff = A(freeRows, freeRows), Afp = A(freeRows, pinRows);
    const Eigen::VectorXd dvFree = Aff.ldlt().solve(b(freeRows) - Afp * dv(pinRows));
    ASSERT_LE((Aff * dvFree - (b(freeRows) - Afp * dv(pinRows))).norm(), 1e-12 * b.norm());
    dv(freeRows) = dvFree;

    auto solver = solverFor("exact");
    ASSERT_TRUE(solver);
    State state = s;
    ASSERT_EQ(solver->step(model, env, state, input).status, StepStatus::Ok);
    const Points dense = Eigen::Map<const Points>(dv.data(), 3, n);
    Index worst = 0;
    (solver->lastDv() - dense).colwise().norm().maxCoeff(&worst);
    EXPECT_LE(relativeError(flat(solver->lastDv()), dv), 1e-8)
        << "dv of 'exact' differs from the dense backward Euler solve; worst particle " << worst
        << (isPinned[worst] ? " (pinned)" : " (free)") << ": " << solver->lastDv().col(worst).transpose()
        << " vs " << dense.col(worst).transpose();

    // The state after the step: v += dv, x += h v for free particles; pins on their targets.
    for (Index i = 0; i < n; ++i) {
        if (isPinned[i]) continue;
        const Vec3 v = s.v.col(i) + dv.segment<3>(3 * i);
        EXPECT_LE((state.v.col(i) - v).norm(), 1e-8 * v.norm()) << "particle " << i;
        EXPECT_LE((state.x.col(i) - (s.x.col(i) + h * v)).norm(), 1e-8 * h * v.norm()) << "particle " << i;
    }
    for (const Pin& p : pins) {
        EXPECT_EQ(state.x.col(p.particle), p.x) << "pinned particle " << p.particle;
        EXPECT_EQ(state.v.col(p.particle), p.v) << "pinned particle " << p.particle;
    }
}

// =============================================================================================
// 6. Determinism: golden hashes. One test per solver and thread count, so that ctest runs each
// in its own process; 1 and 2 threads must reproduce the same recorded hash.

TEST(GoldenHash, KangChoDoubleThreads1) { expectGoldenHash("kangcho", 1); }
TEST(GoldenHash, KangChoDoubleThreads2) { expectGoldenHash("kangcho", 2); }
TEST(GoldenHash, KangChoFloatThreads1) { expectGoldenHash("kangcho:precision=float", 1); }
TEST(GoldenHash, KangChoFloatThreads2) { expectGoldenHash("kangcho:precision=float", 2); }
TEST(GoldenHash, MultigridThreads1) { expectGoldenHash("multigrid", 1); }
TEST(GoldenHash, MultigridThreads2) { expectGoldenHash("multigrid", 2); }
TEST(GoldenHash, MultigridVCycleThreads1) {
    expectGoldenHash("multigrid:tolerance=0.001/v-cycles", 1, [](MultigridTuning& t) { t.kcycleLevels = 0; });
}
TEST(GoldenHash, MultigridColdStartThreads1) {
    expectGoldenHash("multigrid:tolerance=0.001/v-cycles-from-zero", 1, [](MultigridTuning& t) {
        t.kcycleLevels = 0;
        t.startHistory = 0;
    });
}
TEST(GoldenHash, MultigridMixedThreads1) { expectGoldenHash("multigrid:precision=mixed", 1); }
TEST(GoldenHash, MultigridMixedThreads2) { expectGoldenHash("multigrid:precision=mixed", 2); }

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
