#include "cloth/cloth.h"

#include <optional>
#include <stdexcept>

namespace cloth {

namespace {

using Clock = ClothObserver::Clock;

double msBetween(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

// The first particle farther than reach from the anchor, or -1: a runaway step (an unstable
// solver's growth) caught before its numbers overflow.
Index firstRunaway(const State& state, const Vec3& anchor, Scalar reach) {
    const Scalar reach2 = reach * reach;
    for (Index i = 0; i < state.x.cols(); ++i)
        if ((state.x.col(i) - anchor).squaredNorm() > reach2) return i;
    return -1;
}

}  // namespace

const char* toString(ClothStage stage) {
    switch (stage) {
        case ClothStage::Air: return "air";
        case ClothStage::Solve: return "cloth_step";
        case ClothStage::Collision: return "collision";
        case ClothStage::Contact: return "contact";
    }
    return "?";
}

Cloth::Cloth(ClothDesc desc, const ClothSettings& settings, const RigidFrame& carrier)
    : model_(std::move(desc.model)), attachments_(std::move(desc.attachments)), start_(std::move(desc.start)) {
    if (attachments_.empty()) throw std::invalid_argument("cloth: no attachments (a cloth hangs from at least one)");
    if (start_.cols() == 0) start_ = model_.restPositions();
    if (start_.cols() != model_.particleCount()) throw std::invalid_argument("cloth: start shape has the wrong size");
    makeSolver(settings);
    solids_ = std::move(desc.solids);
    collisionSkip_ = std::move(desc.collisionSkip);
    collisionSkip_.resize(std::size_t(model_.particleCount()), 0);
    pinned_.assign(std::size_t(model_.particleCount()), 0);
    for (const Attachment& a : attachments_) {
        if (a.particle < 0 || a.particle >= model_.particleCount())
            throw std::invalid_argument("cloth: attachment of particle " + std::to_string(a.particle) + ": no such particle");
        collisionSkip_[std::size_t(a.particle)] = pinned_[std::size_t(a.particle)] = 1;
        pins_.push_back({a.particle, Vec3::Zero(), Vec3::Zero()});
    }
    const Points& rest = model_.restPositions();
    reach_ = kRunawayReach * (rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).norm();
    reset(carrier);
}

// The solver and its constraints from `settings` (first: a bad one leaves the cloth as it was).
void Cloth::makeSolver(const ClothSettings& settings) {
    std::string error;
    std::unique_ptr<Solver> solver = cloth::makeSolver(settings.solver, &error);
    if (!solver) throw std::invalid_argument("solver: " + error);
    if (const std::string bad = validate(settings.constraints); !bad.empty())
        throw std::invalid_argument("constraints: " + bad);
    if (settings.contact.enabled && (model_.gridNx() < 2 || !(settings.contact.thickness > 0) || !(settings.contact.maxMove > 0)))
        throw std::invalid_argument("contact: needs a grid cloth, a thickness and a move above 0");
    solver->setConstraints(settings.constraints);
    solver->threadPool().setObserver(workerObserver_);
    solver->threadPool().useHost(host_);
    solver_ = std::move(solver);
    settings_ = settings;
}

void Cloth::reconfigure(const ClothSettings& settings, const Model* model) {
    if (model && model->particleCount() != model_.particleCount())
        throw std::invalid_argument("cloth: a running cloth keeps its particles");
    makeSolver(settings);
    if (model) model_ = *model;
    solver_->resetHistory();
}

void Cloth::setWorkerObserver(ThreadPool::Observer observer) {
    workerObserver_ = std::move(observer);
    solver_->threadPool().setObserver(workerObserver_);
}

void Cloth::setTaskSystem(TaskSystem* host) {
    host_ = host;
    solver_->threadPool().useHost(host_);
}

void Cloth::reset(const RigidFrame& carrier) {
    state_ = State::atRest(model_);
    solver_->resetHistory();
    for (Index i = 0; i < model_.particleCount(); ++i) {
        const Vec3 w = carrier.point(start_.col(i));
        state_.x.col(i) = w;
        state_.v.col(i) = carrier.velocityAt(w);
    }
    carrier_ = carrier;
    updatePins(carrier);
}

void Cloth::restart(const State& state, const RigidFrame& carrier) {
    state_ = state;
    solver_->resetHistory();
    carrier_ = carrier;
    updatePins(carrier);
}

void Cloth::updatePins(const RigidFrame& carrier) {
    for (std::size_t k = 0; k < pins_.size(); ++k) {
        pins_[k].x = carrier.point(attachments_[k].local);
        pins_[k].v = carrier.velocityAt(pins_[k].x);
    }
}

bool Cloth::step(Scalar h, const RigidFrame& carrier, const std::vector<Collider>& colliders) {
    profile_ = {};
    const std::vector<Collider> none;
    const std::vector<Collider>& meet = settings_.collisions ? colliders : none;
    // Pins move to the carrier's end-of-tick pose; with substeps they are interpolated linearly
    // from where they are, so they still land exactly on it at the end of the tick.
    const std::vector<Pin> start = pins_;
    const int n = settings_.substeps;
    // A failed single step leaves the state untouched; with substeps, keep the start to go back to.
    std::optional<State> before;
    if (n > 1) before = state_;
    const bool ok = runSubsteps(h, n, carrier, start, meet);
    if (!ok) {
        if (before) state_ = *before;
        solver_->resetHistory();
        pins_ = start;
        if (!runSubsteps(h, 8 * n, carrier, start, meet)) reset(carrier);
    }
    carrier_ = carrier;
    return ok;
}

namespace {

// The carrier a fraction f of the way from a to b: its position on the straight line, its
// rotation on the great arc.
RigidFrame between(const RigidFrame& a, const RigidFrame& b, Scalar f) {
    if (f >= 1) return b;
    RigidFrame c = b;
    c.position = a.position + f * (b.position - a.position);
    c.rotation = a.rotation.slerp(f, b.rotation);
    return c;
}

}  // namespace

bool Cloth::runSubsteps(Scalar h, int n, const RigidFrame& carrier, const std::vector<Pin>& start,
                        const std::vector<Collider>& colliders) {
    for (int s = 1; s <= n; ++s) {
        updatePins(carrier);
        if (s < n)
            for (std::size_t k = 0; k < pins_.size(); ++k)
                pins_[k].x = start[k].x + (pins_[k].x - start[k].x) * (Scalar(s) / n);
        if (!stepOnce(h / n, colliders, between(carrier_, carrier, Scalar(s - 1) / n), between(carrier_, carrier, Scalar(s) / n)))
            return false;
    }
    return true;
}

// The air's forces for this step into `input`, unless the solver evaluates the air itself.
void Cloth::addAir(StepInput& input) {
    if (solver_->couplesAir()) {
        input.air = &settings_.airParams;  // at every iterate (its time is the solver's)
        return;
    }
    if (observer_) observer_->stageBegins(ClothStage::Air);
    const auto t0 = Clock::now();
    airForce_.setZero(3, model_.particleCount());
    addAirForces(model_, state_, settings_.airParams, airForce_, settings_.implicitAir ? &airJacobian_ : nullptr,
                 &solver_->threadPool(), &airWorkspace_);
    input.externalForce = &airForce_;
    if (settings_.implicitAir) {  // backward Euler in the air's velocity too (solvers that cannot, ignore it)
        airDamping(airJacobian_, airDamping_);
        input.damping = &airDamping_;
    }
    const auto t1 = Clock::now();
    profile_.air += msBetween(t0, t1);
    if (observer_) observer_->stageEnded(ClothStage::Air, t0, t1);
}

void Cloth::collide(const std::vector<Collider>& colliders) {
    if (observer_) observer_->stageBegins(ClothStage::Collision);
    const auto t0 = Clock::now();
    resolveCollisions(colliders, settings_.thickness, &collisionSkip_, state_, &solver_->threadPool(),
                      &collisionWorkspace_);
    const auto t1 = Clock::now();
    profile_.collision += msBetween(t0, t1);
    if (observer_) observer_->stageEnded(ClothStage::Collision, t0, t1);
}

// Contact over the step just taken, from xStart_ (the carrier at `from`) to the state (at `to`).
void Cloth::makeContact(const RigidFrame& from, const RigidFrame& to, Scalar h) {
    if (observer_) observer_->stageBegins(ClothStage::Contact);
    contactReport_ = {};
    const auto [t0, t1] = contactOver(from, to, xStart_, state_, h, &solver_->threadPool());
    if (observer_) observer_->stageEnded(ClothStage::Contact, t0, t1);  // the span the profile adds up
}

// The contact stage over one motion, its report added to the step's and its time to the profile's;
// returns when it began and ended.
std::pair<Clock::time_point, Clock::time_point> Cloth::contactOver(const RigidFrame& from, const RigidFrame& to,
                                                                   const Points& xStart, State& state, Scalar h,
                                                                   ParallelFor* loops) {
    const auto t0 = Clock::now();
    const ContactReport r =
        contactStage_.apply(model_, pinned_, xStart, state, from, to, solids_, settings_.contact, h, loops);
    contactReport_ += r, contactTotal_ += r;
    const auto t1 = Clock::now();
    profile_.contact += msBetween(t0, t1);
    return {t0, t1};
}

// Inside the solver's step, on its thread: no stage is told to the observer (it is inside the
// solve's), its time is the profile's contact, taken out of the solve's.
void Cloth::SubstepHook::apply(Scalar f0, Scalar f1, const Points& xStart, State& state, Scalar h, ParallelFor* loops) {
    cloth->contactOver(between(from, to, f0), between(from, to, f1), xStart, state, h, loops);
}

bool Cloth::stepOnce(Scalar h, const std::vector<Collider>& colliders, const RigidFrame& from, const RigidFrame& to) {
    const bool contactInside = settings_.contact.enabled && settings_.contact.substepStride > 0 && solver_->resolvesCollisions();
    if (settings_.contact.enabled && !contactInside) xStart_ = state_.x;
    StepInput input;
    input.h = h;
    input.pins = pins_;
    if (settings_.air) addAir(input);
    const bool collideHere = !colliders.empty();
    if (collideHere && solver_->resolvesCollisions()) {  // at every substep of the solver's
        input.colliders = &colliders;
        input.thickness = settings_.thickness;
        input.collisionSkip = &collisionSkip_;
    }
    if (contactInside) {
        substepHook_ = {};
        substepHook_.cloth = this, substepHook_.from = from, substepHook_.to = to;
        input.contact = &substepHook_;
        contactReport_ = {};
    }
    const double contactBefore = profile_.contact;
    if (observer_) observer_->stageBegins(ClothStage::Solve);
    const auto t0 = observer_ ? Clock::now() : Clock::time_point{};
    const StepResult r = solver_->step(model_, settings_.environment, state_, input);
    if (observer_) observer_->stageEnded(ClothStage::Solve, t0, Clock::now());
    profile_.forces += solver_->profile().forcesMs;
    profile_.solve += solver_->profile().solveMs + solver_->profile().integrateMs - (profile_.contact - contactBefore);
    ++steps_;
    counts_.iterations += r.iterations;
    counts_.maxIterations = std::max(counts_.maxIterations, r.iterations);
    counts_.linearIterations += r.linearIterations;
    if (r.status != StepStatus::Ok) return fail(toString(r.status), r.badParticle);
    if (collideHere && !solver_->resolvesCollisions()) collide(colliders);
    if (settings_.contact.enabled && !contactInside) makeContact(from, to, h);
    if (const Index i = firstRunaway(state_, pins_.front().x, reach_); i >= 0) return fail("diverged", i);
    return true;
}

bool Cloth::fail(const std::string& what, Index particle) {
    if (failures_++ == 0)
        firstFailure_ = "cloth step " + std::to_string(steps_) + ": " + what + " (first bad particle " +
                        std::to_string(particle) + ")";
    return false;
}

}  // namespace cloth
