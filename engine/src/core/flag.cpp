#include "engine/flag.h"

#include "cloth/presets.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "cloth/diagnostics.h"
#include "engine/config_error.h"
#include "engine/profiler.h"

namespace engine {

namespace {

cloth::Model buildModel(const SceneConfig& scene, const PoleMount& mount) {
    const auto& f = scene.flag;
    cloth::GridDesc g;
    g.nx = f.nx;
    g.ny = f.ny;
    g.width = f.width;
    g.height = f.height;
    g.totalMass = f.mass;
    g.stiffness = f.stiffness;
    // In the carrier frame: column 0 on the pole, from its top down; the flag trails behind.
    g.origin = mount.base + Eigen::Vector3d(0, mount.height, 0);
    g.axisU = mount.trailing;
    g.axisV = -Eigen::Vector3d::UnitY();
    try {
        return cloth::Model::fromGrid(g);
    } catch (const std::invalid_argument& e) {
        throw ConfigError(scene.file + ": flag: " + e.what());
    }
}

// The first particle farther than reach from the anchor, or -1: a runaway step (an unstable
// solver's growth) caught before its numbers overflow.
cloth::Index firstRunaway(const cloth::State& state, const Eigen::Vector3d& anchor, double reach) {
    const double reach2 = reach * reach;
    for (cloth::Index i = 0; i < state.x.cols(); ++i)
        if ((state.x.col(i) - anchor).squaredNorm() > reach2) return i;
    return -1;
}

}  // namespace

Flag::Flag(const SceneConfig& scene, const PoleMount& mount, const RigidFrame& carrier)
    : model_(buildModel(scene, mount)), mount_(mount) {
    applySettings(scene);
    air_ = scene.subsystems & kAir;
    collision_ = scene.subsystems & kCollision;
    thickness_ = scene.flag.thickness;
    substeps_ = scene.flag.substeps;
    const cloth::Points& rest = model_.restPositions();
    reach_ = kRunawayReach * (rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).norm();
    pins_ = cloth::pinColumn(model_);  // column 0 at its rest position: the pole edge in pole space
    // Collisions skip the pinned particles and the sleeve: the pinned column runs down the pole's
    // axis, like a sleeve sewn around it, and particles whose rest position lies inside the pole's
    // collision capsule (radius + thickness) belong to it. Colliding them would push them out of
    // the pole every tick against their springs (at 65x65 the second column sits 2.3 cm from the
    // axis, inside the 4.5 cm capsule, and was held at 92% stretch).
    collisionSkip_.assign(model_.particleCount(), 0);
    for (const cloth::Pin& p : pins_) {
        collisionSkip_[p.particle] = 1;
        pinLocal_.push_back(p.x);
    }
    const double sleeve = mount.radius + thickness_;
    for (cloth::Index i = 0; i < model_.particleCount(); ++i) {
        const Eigen::Vector3d d = model_.restPositions().col(i) - mount.base;
        if (std::hypot(d.x(), d.z()) < sleeve) collisionSkip_[i] = 1;
    }
    resetToRest(carrier);
}

// The solver, its constraints, the drag and the air, from the scene's settings.
void Flag::applySettings(const SceneConfig& scene) {
    std::string error;
    std::unique_ptr<cloth::Solver> solver = cloth::makeSolver(scene.flag.solver, &error);
    if (!solver) throw ConfigError(scene.file + ": flag.solver: " + error);
    solver->setConstraints(scene.flag.constraints);
    solver_ = std::move(solver);
    env_.drag = scene.flag.drag;
    implicitAir_ = scene.flag.implicitAir;
    airParams_ = scene.air;
}

void Flag::reconfigure(const SceneConfig& scene) {
    cloth::Model model = buildModel(scene, mount_);
    if (model.particleCount() != model_.particleCount())
        throw ConfigError(scene.file + ": flag.resolution: a running flag keeps its particles");
    applySettings(scene);  // first: a bad solver leaves the flag as it was
    model_ = std::move(model);
    solver_->resetHistory();
    observeWorkers();
}

void Flag::resetToRest(const RigidFrame& carrier) {
    state_ = cloth::State::atRest(model_);
    solver_->resetHistory();
    // No real flag is perfectly flat; a flat sheet pinned along an edge is an (unstable)
    // equilibrium it would never leave. A millimetre-scale ripple across the plane breaks the
    // symmetry the same way every time.
    const Eigen::Vector3d across = mount_.trailing.cross(Eigen::Vector3d::UnitY());
    const int nx = model_.gridNx();
    for (cloth::Index i = 0; i < model_.particleCount(); ++i) {
        const double u = double(i % nx) / (nx - 1), v = double(i / nx) / (model_.gridNy() - 1);
        const Eigen::Vector3d local =
            model_.restPositions().col(i) + 0.003 * u * std::sin(3.0 * u + 2.0 * v) * across;
        const Eigen::Vector3d w = carrier.point(local);
        state_.x.col(i) = w;
        state_.v.col(i) = carrier.velocityAt(w);
    }
    updatePins(carrier);
}

void Flag::restart(const cloth::State& state, const RigidFrame& carrier) {
    state_ = state;
    solver_->resetHistory();
    updatePins(carrier);
}

void Flag::updatePins(const RigidFrame& carrier) {
    for (std::size_t k = 0; k < pins_.size(); ++k) {
        pins_[k].x = carrier.point(pinLocal_[k]);
        pins_[k].v = carrier.velocityAt(pins_[k].x);
    }
}

cloth::Collider Flag::poleCollider(const RigidFrame& carrier) const {
    cloth::Collider c;
    c.shape = cloth::Collider::Shape::Capsule;
    c.axis = carrier.rotation * Eigen::Vector3d::UnitY();
    c.center = carrier.point(mount_.base + Eigen::Vector3d(0, mount_.height / 2, 0));
    c.halfExtents = Eigen::Vector3d(mount_.height / 2, 0, 0);
    c.radius = mount_.radius;
    c.velocity = carrier.velocityAt(c.center);
    return c;
}

void Flag::setTrace(Trace* trace) {
    trace_ = trace;
    if (trace) traceNames_ = {trace->nameId(phaseName(Phase::Air)), trace->nameId(phaseName(Phase::ClothForces)),
                              trace->nameId(phaseName(Phase::ClothSolve)), trace->nameId(phaseName(Phase::Collision)),
                              trace->nameId("cloth_step")};
    observeWorkers();
}

// The solver's pool tells when its workers ran; they become events on their own rows, named
// after the stage that split the work (air, cloth_step, collision).
void Flag::observeWorkers() {
    if (!trace_) {
        solver_->threadPool().setObserver(nullptr);
        return;
    }
    solver_->threadPool().setObserver([this](int worker, Trace::Clock::time_point b, Trace::Clock::time_point e) {
        trace_->complete(stage_, Trace::Category::Worker, b, e, -1, worker);
    });
}

// The forces from the step's start, the solve (with the integration after it) up to its end;
// neither leaves the span, and they never overlap (the solver timed them inside it, one after
// the other).
void Flag::traceStep(Trace::Clock::time_point begin, Trace::Clock::time_point end) const {
    using Clock = Trace::Clock;
    auto span = [](double ms) {
        return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
    };
    const cloth::StepProfile& p = solver_->profile();
    const Clock::time_point forcesEnd = std::min(begin + span(p.forcesMs), end);
    const Clock::time_point solveBegin = std::max(end - span(p.solveMs + p.integrateMs), forcesEnd);
    trace_->complete(traceNames_.forces, Trace::Category::Phase, begin, forcesEnd);
    trace_->complete(traceNames_.solve, Trace::Category::Phase, solveBegin, end);
}

bool Flag::stepOnce(double h, const std::vector<cloth::Collider>& colliders) {
    using Clock = Trace::Clock;
    cloth::StepInput input;
    input.h = h;
    input.pins = pins_;
    if (air_ && solver_->couplesAir()) {
        input.air = &airParams_;  // the solver evaluates the air at every iterate (its time is the solver's)
    } else if (air_) {
        stage_ = traceNames_.air;
        const auto t0 = Clock::now();
        airForce_.setZero(3, model_.particleCount());
        cloth::addAirForces(model_, state_, airParams_, airForce_, implicitAir_ ? &airJacobian_ : nullptr,
                            &solver_->threadPool(), &airWorkspace_);
        input.externalForce = &airForce_;
        if (implicitAir_) {  // backward Euler in the air's velocity too (solvers that cannot, ignore it)
            cloth::airDamping(airJacobian_, airDamping_);
            input.damping = &airDamping_;
        }
        const auto t1 = Clock::now();
        timings_.air += Profiler::ms(t1 - t0);
        if (trace_) trace_->complete(traceNames_.air, Trace::Category::Phase, t0, t1);
    }
    const bool collideHere = collision_ && !colliders.empty();
    if (collideHere && solver_->resolvesCollisions()) {  // at every substep of the solver's
        input.colliders = &colliders;
        input.thickness = thickness_;
        input.collisionSkip = &collisionSkip_;
    }
    stage_ = traceNames_.step;
    const auto stepBegin = trace_ ? Clock::now() : Clock::time_point{};
    const cloth::StepResult r = solver_->step(model_, env_, state_, input);
    if (trace_) traceStep(stepBegin, Clock::now());
    timings_.forces += solver_->profile().forcesMs;
    timings_.solve += solver_->profile().solveMs + solver_->profile().integrateMs;
    ++steps_;
    counts_.iterations += r.iterations;
    counts_.maxIterations = std::max(counts_.maxIterations, r.iterations);
    counts_.linearIterations += r.linearIterations;
    if (r.status != cloth::StepStatus::Ok) return fail(cloth::toString(r.status), r.badParticle);
    if (collideHere && !solver_->resolvesCollisions()) {
        stage_ = traceNames_.collision;
        const auto t0 = Clock::now();
        cloth::resolveCollisions(colliders, thickness_, &collisionSkip_, state_, &solver_->threadPool(),
                                 &collisionWorkspace_);
        const auto t1 = Clock::now();
        timings_.collision += Profiler::ms(t1 - t0);
        if (trace_) trace_->complete(traceNames_.collision, Trace::Category::Phase, t0, t1);
    }
    if (const cloth::Index i = firstRunaway(state_, pins_.front().x, reach_); i >= 0) return fail("diverged", i);
    return true;
}

bool Flag::fail(const std::string& what, cloth::Index particle) {
    if (failures_++ == 0)
        firstFailure_ = "cloth step " + std::to_string(steps_) + ": " + what + " (first bad particle " +
                        std::to_string(particle) + ")";
    return false;
}

void Flag::tick(double h, const RigidFrame& carrier, const std::vector<cloth::Collider>& colliders) {
    // Pins move to the carrier's end-of-tick pose; with substeps they are interpolated linearly
    // from where they are, so they still land exactly on the pole at the end of the tick.
    const std::vector<cloth::Pin> start = pins_;
    auto runSubsteps = [&](int n) {
        for (int s = 1; s <= n; ++s) {
            updatePins(carrier);
            if (s < n)
                for (std::size_t k = 0; k < pins_.size(); ++k)
                    pins_[k].x = start[k].x + (pins_[k].x - start[k].x) * (double(s) / n);
            if (!stepOnce(h / n, colliders)) return false;
        }
        return true;
    };
    // A failed single step leaves the state untouched; with substeps, keep the start to go back to.
    std::optional<cloth::State> before;
    if (substeps_ > 1) before = state_;
    if (runSubsteps(substeps_)) return;
    if (before) state_ = *before;
    solver_->resetHistory();
    pins_ = start;
    if (runSubsteps(8 * substeps_)) return;
    resetToRest(carrier);
}

}  // namespace engine
