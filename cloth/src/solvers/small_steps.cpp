// small_steps: the true motion's own integrator made fast. Symplectic Euler in small substeps,
// the air and the collisions at every substep, the pins moving along the carrier's path within
// the step: the same model as the study's fine-step reference (its explicit steps, air and
// collisions per substep), in float SIMD on the grid's stencil (small_steps/stencil_cloth.h),
// positions relative to the first pin so float keeps its precision anywhere in the world, on one
// or more threads that meet twice per substep, four times with constraints (the same bits for any
// count; beside a busy core they part, small_steps/lag_guard.h; a thread that has not begun when
// the step starts is not waited for, small_steps/start_gate.h; a cloth under `parallel_from`
// particles steps on one thread). substeps=0 picks each step's
// count from the stability bound (small_steps/stable_step.h) times `fraction`, and with
// max_move > 0 enough that no pin, and no particle at its speed relative to the pole's, moves
// more than max_move metres in a substep: as the reference paces its substeps through a teleport,
// and after it while the flag still flies. The flag's constraints (tethers, the stretch limit) run
// after every substep, as they do after each of the reference's, and so does the caller's contact
// (StepInput::contact) when it hands one in, on thread 0 with the others serving its loops
// (small_steps/crew.h).
// Grids only (Model::fromGrid's layout); on another mesh every step fails and details() says why.

#include <algorithm>
#include <atomic>
#include <memory>

#include "cloth/air.h"
#include "cloth/collision.h"
#include "cloth/diagnostics.h"
#include "cloth/solvers/small_steps_settings.h"
#include "cloth/solver_kind.h"
#include "small_steps/collisions.h"
#include "small_steps/constraint_check.h"
#include "small_steps/crew.h"
#include "small_steps/kernels.h"
#include "small_steps/lag_guard.h"
#include "small_steps/spin_barrier.h"
#include "small_steps/start_gate.h"
#include "small_steps/stable_step.h"
#include "solvers/step_common.h"

namespace cloth {

namespace {


// The pinned particles' targets per substep, and the constant part of each substep's forces.
struct StepPlan {
    IntegrateConstants integrate;
    AirConstants air;
    int substeps = 1;
    Scalar h = 0;  // of a substep
    std::vector<int> pinned;            // particles
    std::vector<Vec3> pinStart, pinEnd;  // relative to the origin
};

class SmallStepsSolver final : public Solver {
public:
    bool couplesAir() const override { return true; }
    bool resolvesCollisions() const override { return true; }
    std::string details() const override {
        return layoutError_.empty() ? "substeps in the last step: " + std::to_string(lastSubsteps_) : layoutError_;
    }

    StepResult step(const Model& model, const Environment& env, State& state, const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        if (model.id() != cloth_.modelId && !prepare(model)) return {StepStatus::SolverFailed, -1};
        profile_ = {};
        auto t0 = Clock::now();
        load(model, env, state, input);
        profile_.forcesMs = msSince(t0);
        t0 = Clock::now();
        model_ = &model, pins_ = &input.pins;
        runSubsteps();
        profile_.solveMs = msSince(t0);
        t0 = Clock::now();
        store();
        // The constraints ran after every substep: none are left for the step's end.
        StepResult result = commitStep(model, constraints_.any() ? noConstraints_ : constraints_, input, *pool_, state,
                                   scratch_, StepResult{});
        result.iterations = plan_.substeps;
        profile_.integrateMs = msSince(t0);
        return result;
    }

private:
    const SmallStepsSettings& own() const { return settings<SmallStepsSettings>(); }

    bool prepare(const Model& model) {
        layoutError_ = cloth_.build(model);
        if (!layoutError_.empty()) return false;
        s_.assign(cloth_);
        pinnedMask_.assign(cloth_.n, cloth_.pad);
        pinPos_.assign(cloth_.n, cloth_.pad), pinVel_.assign(cloth_.n, cloth_.pad), external_.assign(cloth_.n, cloth_.pad);
        springFrequency_ = springFrequencyBound(model);
        const int threads = cloth_.n >= own().parallelFrom ? pool_->threads() : 1;
        ranges_.clear();
        for (int t = 0; t <= threads; ++t) ranges_.push_back(int((long long)cloth_.n * t / threads) / 8 * 8);
        ranges_.back() = cloth_.n;
        barrier_ = std::make_unique<SpinBarrier>(threads);
        crew_ = std::make_unique<Crew>(threads);
        return true;
    }

    void load(const Model& model, const Environment& env, const State& state, const StepInput& input);
    void loadPins(const StepInput& input);
    int substepsOf(const Model& model, const State& state, const StepInput& input) const;
    void runSubsteps();
    void worker(int index, int begin, int end, bool together, std::uint32_t sessions);
    void meet(int index);
    bool meetAtEnd(int index);
    float fastestRelative(int begin, int end) const;
    bool contactDue(int sub, bool together, Scalar& since, int& last) const;
    void constrain();
    void contactAfter(int sub, std::uint32_t session);
    void setState(const State& state);
    void worldPositions(Points& out) const;
    void worldState(State& out) const;
    void store();

    StencilCloth cloth_;
    StencilState s_;
    PaddedField pinnedMask_;
    Vec3Field pinPos_, pinVel_, external_;
    StepPlan plan_;
    SubstepColliders colliders_;
    Vec3 origin_ = Vec3::Zero();
    Points startV_;
    State scratch_;
    Scalar springFrequency_ = 0;
    std::vector<int> ranges_;  // thread t takes particles [ranges_[t], ranges_[t + 1])
    std::unique_ptr<SpinBarrier> barrier_;
    std::unique_ptr<Crew> crew_;     // the threads as the contact's loops' runner
    std::uint32_t crewSessions_ = 0;  // contacts the threads have run together so far
    StartGate gate_;  // the step's threads all begun, or thread 0 alone
    LagGuard lag_;  // one thread for a while when a busy core keeps the other waiting
    Clock::time_point stepStart_;    // when the parallel step under way began
    std::atomic<bool> parting_{false};  // thread 0 ends this step alone
    Scalar moveStride_ = 0;             // contact after this move relative to the pole (0: by stride())
    float poleV_[3] = {0, 0, 0};        // the pole's velocity over the step
    std::vector<float> fastest_;        // per thread: its particles' largest squared speed relative to the pole
    std::string layoutError_;
    int lastSubsteps_ = 0;
    const Model* model_ = nullptr;         // the model and the pins of the step under way
    const std::vector<Pin>* pins_ = nullptr;
    State constrained_;                    // the substep's state in double for the constraints
    ConstraintCheck check_;                // what the constraints need check, in float
    SubstepContact* contact_ = nullptr;    // the step's contact, after every contact_->stride() substeps (or null)
    int contactFrom_ = 0;                  // the substep the last contact ended
    State contactEnd_;                     // the substep's end in the world, in double, for contact
    Points contactStart_;                  // and its start
    ConstraintSet noConstraints_;
};

// The velocity of the pole the flag hangs on: its first pin's (zero without a pin).
Vec3 poleVelocity(const StepInput& input) { return input.pins.empty() ? Vec3::Zero() : input.pins.front().v; }

// The state relative to the origin (the first pin where the step starts), the pins, the air, the
// colliders, and the substeps of this step.
void SmallStepsSolver::load(const Model& model, const Environment& env, const State& state, const StepInput& input) {
    origin_ = input.pins.empty() ? Vec3(state.x.col(0)) : Vec3(state.x.col(input.pins.front().particle));
    setState(state);
    startV_ = state.v;
    loadPins(input);
    IntegrateConstants& c = plan_.integrate;
    c.gx = float(env.gravity.x()), c.gy = float(env.gravity.y()), c.gz = float(env.gravity.z());
    c.drag = float(env.drag);
    c.air = input.air != nullptr;
    if (input.air) {
        const AirParams& a = *input.air;
        plan_.air = {float(a.wind.x()), float(a.wind.y()), float(a.wind.z()), float(a.density / 4 / 3),
                     float(a.dragCoefficient - a.frictionCoefficient + a.liftCoefficient), float(a.frictionCoefficient),
                     float(a.liftCoefficient)};
    }
    c.extX = c.extY = c.extZ = nullptr;
    if (input.externalForce) {
        for (Index i = 0; i < cloth_.n; ++i)
            external_.x.at()[i] = float((*input.externalForce)(0, i)), external_.y.at()[i] = float((*input.externalForce)(1, i)),
            external_.z.at()[i] = float((*input.externalForce)(2, i));
        c.extX = external_.x.at(), c.extY = external_.y.at(), c.extZ = external_.z.at();
    }
    colliders_.prepare(input.colliders, input.thickness, input.collisionSkip, origin_);
    if (constraints_.any()) check_.prepare(cloth_, model, input.pins, constraints_);
    contact_ = input.contact;
    moveStride_ = contact_ ? contact_->strideMove() : 0;
    fastest_.assign(std::size_t(pool_->threads()), 0.0f);
    const Vec3 pv = poleVelocity(input);
    poleV_[0] = float(pv.x()), poleV_[1] = float(pv.y()), poleV_[2] = float(pv.z());
    if (contact_) worldPositions(contactStart_), contactFrom_ = 0;
    plan_.substeps = substepsOf(model, state, input);
    lastSubsteps_ = plan_.substeps;
    plan_.h = input.h / plan_.substeps;
    c.h = float(plan_.h);
}

// This step's substeps: the fixed count, or the stability bound's, and with max_move the paced
// count where it is larger (the step's largest move is measured only then).
int SmallStepsSolver::substepsOf(const Model& model, const State& state, const StepInput& input) const {
    if (own().substeps > 0) return own().substeps;
    const int stable = stableSubsteps(input.h, springFrequency_, airRateBound(model, state, input.air), own().fraction);
    if (own().maxMove <= 0) return stable;
    const Scalar move = largestMove(plan_.pinStart, plan_.pinEnd, state, poleVelocity(input), input.h);
    return std::max(stable, pacedSubsteps(move, own().maxMove));
}

// The pinned particles move on a straight line from where they are to their targets over the
// step, with their targets' velocity (as engine::Flag moves them over its substeps).
void SmallStepsSolver::loadPins(const StepInput& input) {
    std::fill(pinnedMask_.storage.begin(), pinnedMask_.storage.end(), 0.0f);
    plan_.pinned.clear(), plan_.pinStart.clear(), plan_.pinEnd.clear();
    for (const Pin& p : input.pins) {
        if (p.particle < 0 || p.particle >= cloth_.n) continue;
        const int i = int(p.particle);
        pinnedMask_.at()[i] = 1;
        plan_.pinned.push_back(i);
        plan_.pinStart.push_back(Vec3(s_.x.x.at()[i], s_.x.y.at()[i], s_.x.z.at()[i]));
        plan_.pinEnd.push_back(p.x - origin_);
        pinVel_.x.at()[i] = float(p.v.x()), pinVel_.y.at()[i] = float(p.v.y()), pinVel_.z.at()[i] = float(p.v.z());
    }
    IntegrateConstants& c = plan_.integrate;
    c.pinned = pinnedMask_.at();
    c.pinX = pinPos_.x.at(), c.pinY = pinPos_.y.at(), c.pinZ = pinPos_.z.at();
    c.pinVX = pinVel_.x.at(), c.pinVY = pinVel_.y.at(), c.pinVZ = pinVel_.z.at();
}

void SmallStepsSolver::runSubsteps() {
    const int threads = int(ranges_.size()) - 1;  // 1 under parallel_from particles
    const std::uint32_t sessions = crewSessions_;
    if (threads == 1 || lag_.solo()) return worker(0, 0, cloth_.n, false, sessions);
    stepStart_ = Clock::now();
    parting_.store(false, std::memory_order_relaxed);
    gate_.open(threads);
    pool_->run(2 * threads, [this, sessions](int begin, int) {
        const int t = begin / 2;
        if (t != 0) {
            if (gate_.join(t)) worker(t, ranges_[std::size_t(t)], ranges_[std::size_t(t) + 1], true, sessions);
            return;
        }
        // A thread that has not begun by kMinLag (asleep, off its core, or a host's task not yet
        // run) leaves its share to thread 0: the wait counts as one at a barrier.
        const auto t0 = Clock::now();
        const bool together = gate_.lead(LagGuard::kMinLag);
        lag_.waited(Clock::now() - t0);
        if (together) worker(0, ranges_[0], ranges_[1], true, sessions);
        else worker(0, 0, cloth_.n, false, sessions);
    });
    lag_.stepEnded(Clock::now() - stepStart_);
}

// The threads meet; thread 0's wait is judged (LagGuard; whichever thread runs it, only it writes
// the guard, and the caller reads it after the pool's region has ended).
void SmallStepsSolver::meet(int index) {
    if (index != 0) return barrier_->wait();
    const auto t0 = Clock::now();
    barrier_->wait();
    lag_.waited(Clock::now() - t0);
}

// The substep's last meeting, where the threads may part (LagGuard::partNow): thread 0 decides
// before it arrives, and the barrier that releases the others publishes the decision. True: the
// threads go on together.
bool SmallStepsSolver::meetAtEnd(int index) {
    if (index == 0) parting_.store(lag_.partNow(Clock::now() - stepStart_), std::memory_order_relaxed);
    meet(index);
    return !parting_.load(std::memory_order_relaxed);
}

// Thread `index`'s share of every substep (particles [begin, end)): the springs and the air at its
// slots, then, once every thread's are done, its particles' integration; with constraints, its
// slots' test against their bounds and, once every thread's is done, the constraints (on thread
// 0); then its particles' collisions. Alone (together false) it takes every particle. Contact
// runs on thread 0, the others serving its loops (Crew): `sessions` is the crew's count of contacts
// before this step.
void SmallStepsSolver::worker(int index, int begin, int end, bool together, std::uint32_t sessions) {
    Scalar since = 0;  // the fastest particle's move relative to the pole since the last contact
    int last = 0;      // the substep the last contact followed
    for (int sub = 1; sub <= plan_.substeps; ++sub) {
        if (index == 0) {
            const Scalar along = Scalar(sub) / plan_.substeps;
            for (std::size_t k = 0; k < plan_.pinned.size(); ++k) {
                const Vec3 x = plan_.pinStart[k] + along * (plan_.pinEnd[k] - plan_.pinStart[k]);
                const int i = plan_.pinned[k];
                pinPos_.x.at()[i] = float(x.x()), pinPos_.y.at()[i] = float(x.y()), pinPos_.z.at()[i] = float(x.z());
            }
        }
        for (int f = 0; f < int(cloth_.offsets.size()); ++f) springKernel(cloth_, f, s_, begin, end);
        if (plan_.integrate.air) airKernel(cloth_, plan_.air, s_, begin, end);
        if (together) meet(index);
        integrateKernel(cloth_, plan_.integrate, s_, begin, end);
        if (constraints_.any()) {  // between the integration and the collisions, as after a solver's step
            if (together) meet(index);
            check_.test(cloth_, s_.x, begin, end);  // each thread its slots' springs and particles
            if (together) meet(index);
            if (index == 0) constrain();
            if (together) meet(index);
        }
        if (colliders_.any()) colliders_.resolve(s_, begin, end);
        if (contact_ && moveStride_ > 0) fastest_[std::size_t(index)] = fastestRelative(begin, end);
        if (together && !meetAtEnd(index)) {  // a busy core: thread 0 ends the step alone
            if (index != 0) return;
            together = false, begin = 0, end = cloth_.n;
        }
        if (contact_ && contactDue(sub, together, since, last)) {  // after every thread's collisions, on thread 0
            if (together) ++sessions;
            if (index == 0) contactAfter(sub, together ? sessions : 0);
            else crew_->serve(sessions);
            if (together) meet(index);
        }
    }
    if (index == 0) crewSessions_ = sessions;
}

// The largest squared speed of particles [begin, end) relative to the pole.
float SmallStepsSolver::fastestRelative(int begin, int end) const {
    return fastestSquaredKernel(s_.v.x.at(), s_.v.y.at(), s_.v.z.at(), poleV_, begin, end);
}

// Whether contact runs after substep `sub`: after its last, and after every stride() substeps; with
// a move stride, only once the fastest particle relative to the pole has also moved that far since
// the last contact (`since` and `last`, each thread's own copies: the same arithmetic on the same
// data).
bool SmallStepsSolver::contactDue(int sub, bool together, Scalar& since, int& last) const {
    if (moveStride_ <= 0) return sub % contact_->stride() == 0 || sub == plan_.substeps;
    float most = fastest_[0];
    if (together)
        for (float f : fastest_) most = std::max(most, f);
    since += std::sqrt(Scalar(most)) * plan_.h;
    if (sub != plan_.substeps && (sub - last < contact_->stride() || since < moveStride_)) return false;
    since = 0, last = sub;
    return true;
}

// A state in the world, in double, into the float fields: positions relative to the origin.
void SmallStepsSolver::setState(const State& state) {
    float *x = s_.x.x.at(), *y = s_.x.y.at(), *z = s_.x.z.at(), *vx = s_.v.x.at(), *vy = s_.v.y.at(), *vz = s_.v.z.at();
    for (Index i = 0; i < cloth_.n; ++i) {
        const Vec3 r = state.x.col(i) - origin_;
        x[i] = float(r.x()), y[i] = float(r.y()), z[i] = float(r.z());
        vx[i] = float(state.v(0, i)), vy[i] = float(state.v(1, i)), vz[i] = float(state.v(2, i));
    }
}

// The positions in the world, in double: x = origin + relative position.
void SmallStepsSolver::worldPositions(Points& out) const {
    out.resize(3, cloth_.n);
    const float *x = s_.x.x.at(), *y = s_.x.y.at(), *z = s_.x.z.at();
    for (Index i = 0; i < cloth_.n; ++i) out.col(i) = origin_ + Vec3(x[i], y[i], z[i]);
}

// The state in the world, in double (setState's inverse up to float rounding).
void SmallStepsSolver::worldState(State& out) const {
    worldPositions(out.x);
    out.v.resize(3, cloth_.n);
    const float *vx = s_.v.x.at(), *vy = s_.v.y.at(), *vz = s_.v.z.at();
    for (Index i = 0; i < cloth_.n; ++i) out.v.col(i) = Vec3(vx[i], vy[i], vz[i]);
}

// The caller's contact over the substeps since the last contact to `sub`, in double in the world,
// and back (the next substep starts where it left the positions, rounded to float). Its
// corrections change the velocities by correction / the last substep's length (SubstepContact).
// With a crew session (not 0) the other threads serve its loops until it closes; its late waits
// count as the lag guard's.
void SmallStepsSolver::contactAfter(int sub, std::uint32_t session) {
    worldState(contactEnd_);
    const Scalar n = plan_.substeps;
    struct Session {  // closed however apply ends, so that no serving thread waits on
        Crew* crew;
        ~Session() {
            if (crew) crew->close();
        }
    } served{session ? crew_.get() : nullptr};
    if (served.crew) served.crew->open(session);
    contact_->apply(Scalar(contactFrom_) / n, Scalar(sub) / n, contactStart_, contactEnd_, plan_.h, served.crew);
    if (served.crew) lag_.waited(served.crew->late());
    contactFrom_ = sub;
    setState(contactEnd_);
    worldPositions(contactStart_);
}

// The flag's constraints after a substep, on one thread (the same bits for any thread count): what
// the threads' float tests found may be over its bound (ConstraintCheck), then, if anything, the positions relative
// to the origin and the velocities in double (exactly), corrected, and back in float where a
// constraint moved a particle. The constraints read differences of positions only, so
// the relative positions serve.
void SmallStepsSolver::constrain() {
    const ConstraintHints& hints = check_.collect(cloth_);
    if (hints.empty()) return;  // nothing near its bound
    float *x = s_.x.x.at(), *y = s_.x.y.at(), *z = s_.x.z.at(), *vx = s_.v.x.at(), *vy = s_.v.y.at(), *vz = s_.v.z.at();
    constrained_.x.resize(3, cloth_.n), constrained_.v.resize(3, cloth_.n);
    for (Index i = 0; i < cloth_.n; ++i) {
        constrained_.x.col(i) = Vec3(x[i], y[i], z[i]);
        constrained_.v.col(i) = Vec3(vx[i], vy[i], vz[i]);
    }
    if (constraints_.apply(*model_, *pins_, plan_.h, constrained_, nullptr, &hints) == 0) return;
    constraints_.forEachMoved([&](Index i) {  // the others are as they were
        x[i] = float(constrained_.x(0, i)), y[i] = float(constrained_.x(1, i)), z[i] = float(constrained_.x(2, i));
        vx[i] = float(constrained_.v(0, i)), vy[i] = float(constrained_.v(1, i)), vz[i] = float(constrained_.v(2, i));
    });
}

// Back to the world, in double; dv over the step.
void SmallStepsSolver::store() {
    worldState(scratch_);
    dv_ = scratch_.v - startV_;
}

}  // namespace

FLAGSIM_SOLVER_KIND(small_steps) {
    using S = SmallStepsSettings;
    using key = SolverKeys;
    return {"small_steps",
            "symplectic Euler in small substeps, the air, the constraints and collisions at every one (the true motion's "
            "integrator), in float SIMD relative to the pole",
            defaultsTo<S>,
            withCommon({key::shown(key::integer("substeps", &S::substeps, 0, 100000,
                                                "substeps per step; 0 = each step's from the stability bound")),
                        key::real("fraction", &S::fraction, 0, 4, true, false,
                                  "substeps=0: this fraction of the stability bound's longest substep"),
                        key::real("max_move", &S::maxMove, 0, 1, false, false,
                                  "substeps=0: no pin, and no particle relative to the pole, moves farther in a "
                                  "substep (m; 0 = off)"),
                        threadsKey<S>(),
                        key::integer("parallel_from", &S::parallelFrom, 0, 1 << 30,
                                     "a cloth of fewer particles steps on one thread whatever `threads` (its "
                                     "substeps share too little work between the threads' meetings)")},
                       false),
            {},
            createSolver<SmallStepsSolver>};
}

}  // namespace cloth
