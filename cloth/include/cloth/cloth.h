#pragma once
// A cloth as a host steps it: the model, its state, the solver and its constraints, the air and
// the colliders, attached to a rigid carrier. Cloth::step runs one tick's stages in their order
// and fills one profile, as Box2D's b2World_Step and Jolt's PhysicsSystem::Update own theirs:
//
//   per substep:  pins     the attachments to the carrier's end-of-tick pose, interpolated
//                 air      the air's forces (and with implicit air its velocity blocks), unless
//                          the solver evaluates the air itself (Solver::couplesAir)
//                 solve    the solver's step: forces, solve, integration, the constraints; the
//                          colliders too when the solver meets them at every substep
//                          (Solver::resolvesCollisions)
//                 collide  the colliders, after the solve (the other solvers)
//                 contact  no edge through the carrier's solids or through the cloth, over the
//                          step's whole motion (contact.h; with settings.contact.enabled); a
//                          solver that takes its own substeps and meets the colliders at each
//                          (small_steps) runs it after each of them instead (StepInput::contact),
//                          as contact after a whole step of many substeps would hold back
//                          particles the springs then pull through
//                 check    finite, and no particle beyond the runaway reach
//   on failure:   the tick again in 8x the substeps from its start; failing that, back to the
//                 start shape on the carrier. Every failure is counted, the first one described.
//
// The host hands in the carrier's pose and the colliders each tick and reads the state and the
// profile back; it never orders the stages itself.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cloth/air.h"
#include "cloth/collision.h"
#include "cloth/constraints.h"
#include "cloth/contact.h"
#include "cloth/rigid_frame.h"
#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "cloth/thread_pool.h"

namespace cloth {

// A pinned particle and where it sits in the carrier's frame.
struct Attachment {
    Index particle = 0;
    Vec3 local = Vec3::Zero();
};

// What a cloth is made of, in its carrier's frame.
struct ClothDesc {
    Model model;
    std::vector<Attachment> attachments;
    // The positions it starts from and resets to (3 x n, carrier frame); empty: the model's rest.
    Points start;
    // Particles the colliders leave alone (a sleeve round a pole); the attachments always are.
    std::vector<std::uint8_t> collisionSkip;
    // Solids the carrier holds, in its frame (capsules, boxes: their radius and half sizes the
    // solid itself), which contact keeps every edge of the cloth out of (contact.h).
    std::vector<Collider> solids;
};

// How it is stepped (Jolt's *Settings: a public struct filled in by code; a scene file maps onto it).
struct ClothSettings {
    SolverConfig solver;      // the paper's step by default
    Constraints constraints;  // tethers and the stretch limit (none)
    Environment environment;  // gravity and linear drag
    bool air = false;         // the air's forces on the triangles
    AirParams airParams;
    bool implicitAir = true;  // the air's velocity blocks in an implicit solve (air.h)
    bool collisions = false;  // meet the colliders step() is given
    Scalar thickness = 0.015; // m kept between a particle and a collider
    int substeps = 1;         // solver steps per tick
    ContactSettings contact;  // edges kept out of the carrier's solids and out of each other (off)
};

// What the last tick cost, per stage (milliseconds, summed over its substeps).
struct ClothProfile {
    double air = 0, forces = 0, solve = 0, collision = 0, contact = 0;
};

// The solver's iterations, summed over the steps since construction.
struct ClothCounts {
    long long iterations = 0;
    int maxIterations = 0;           // the most in one step
    long long linearIterations = 0;  // newton: GMRES iterations
};

enum class ClothStage { Air, Solve, Collision, Contact };
const char* toString(ClothStage stage);

// A host's view of the stages as they run (a trace), on the calling thread. A solve's forces and
// solve are reported as durations in the solver's profile (Cloth::solver().profile()).
struct ClothObserver {
    using Clock = std::chrono::steady_clock;
    virtual ~ClothObserver() = default;
    virtual void stageBegins(ClothStage) {}
    virtual void stageEnded(ClothStage, Clock::time_point /*begin*/, Clock::time_point /*end*/) {}
};

class Cloth {
public:
    // Throws std::invalid_argument naming the setting when the solver or constraints are invalid.
    Cloth(ClothDesc desc, const ClothSettings& settings, const RigidFrame& carrier);

    // One tick of length h, the carrier at its end-of-tick pose, against `colliders` (world
    // space; ignored unless settings.collisions). False when the tick failed and was recovered.
    bool step(Scalar h, const RigidFrame& carrier, const std::vector<Collider>& colliders);

    // New settings (and, when given, a model with the same particles: a new stiffness or mass),
    // keeping the state. Throws std::invalid_argument, leaving the cloth as it was.
    void reconfigure(const ClothSettings& settings, const Model* model = nullptr);
    // Back to the start shape on the carrier at its pose (what a failed tick's recovery does).
    void reset(const RigidFrame& carrier);
    // Moves the cloth to `state` (a reference run's, for a restart), pins on `carrier`; the solver
    // forgets its history.
    void restart(const State& state, const RigidFrame& carrier);

    const Model& model() const { return model_; }
    const State& state() const { return state_; }
    State& mutableState() { return state_; }  // tests inject faults through this
    const ClothSettings& settings() const { return settings_; }
    const Solver& solver() const { return *solver_; }
    const std::vector<Pin>& pins() const { return pins_; }
    const std::vector<std::uint8_t>& collisionSkip() const { return collisionSkip_; }
    const ClothProfile& profile() const { return profile_; }
    const ClothCounts& counts() const { return counts_; }
    const ContactReport& contactReport() const { return contactReport_; }  // the last step's
    const ContactReport& contactTotal() const { return contactTotal_; }     // since construction
    const std::vector<Collider>& solids() const { return solids_; }
    long long steps() const { return steps_; }
    int failures() const { return failures_; }
    const std::string& firstFailure() const { return firstFailure_; }

    // The host's observer (null: none); kept across reconfigure().
    void setObserver(ClothObserver* observer) { observer_ = observer; }
    // When each of the solver's workers ran (ThreadPool::setObserver); kept across reconfigure().
    void setWorkerObserver(ThreadPool::Observer observer);
    // The host's task system runs the solver's parallel work (cloth/task_system.h; null, the
    // default: the solver's own threads); the same bits either way. The host must outlive the
    // cloth, or be unset first. Kept across reconfigure().
    void setTaskSystem(TaskSystem* host);
    // A step that leaves a particle farther than this many diagonals of the model's rest shape
    // from the first attachment has diverged.
    static constexpr Scalar kRunawayReach = 10;

private:
    bool runSubsteps(Scalar h, int n, const RigidFrame& carrier, const std::vector<Pin>& start,
                     const std::vector<Collider>& colliders);
    bool stepOnce(Scalar h, const std::vector<Collider>& colliders, const RigidFrame& from, const RigidFrame& to);
    void makeContact(const RigidFrame& from, const RigidFrame& to, Scalar h);
    std::pair<ClothObserver::Clock::time_point, ClothObserver::Clock::time_point> contactOver(
        const RigidFrame& from, const RigidFrame& to, const Points& xStart, State& state, Scalar h, ParallelFor* loops);
    // The contact stage at the solver's own substeps, the carrier between the step's two poses.
    struct SubstepHook final : SubstepContact {
        Cloth* cloth = nullptr;
        RigidFrame from, to;
        void apply(Scalar f0, Scalar f1, const Points& xStart, State& state, Scalar h, ParallelFor* loops) override;
        int stride() const override { return cloth->settings_.contact.substepStride; }
        Scalar strideMove() const override { return cloth->settings_.contact.strideMove; }
    };
    void addAir(StepInput& input);
    void collide(const std::vector<Collider>& colliders);
    bool fail(const std::string& what, Index particle);
    void updatePins(const RigidFrame& carrier);
    void makeSolver(const ClothSettings& settings);

    Model model_;
    State state_;
    ClothSettings settings_;
    std::unique_ptr<Solver> solver_;
    std::vector<Attachment> attachments_;
    Points start_;
    std::vector<Pin> pins_;
    std::vector<std::uint8_t> collisionSkip_, pinned_;
    std::vector<Collider> solids_;
    RigidFrame carrier_;  // where the last tick left the carrier
    ContactStage contactStage_;
    ContactReport contactReport_;  // summed over the solver's substeps when it runs them
    ContactReport contactTotal_;   // every application's since construction
    SubstepHook substepHook_;
    Points xStart_;  // the step's start, for contact
    Scalar reach_ = 0;
    Points airForce_;
    std::vector<Mat3> airJacobian_, airDamping_;
    AirWorkspace airWorkspace_;
    CollisionWorkspace collisionWorkspace_;
    ClothProfile profile_;
    ClothCounts counts_;
    ClothObserver* observer_ = nullptr;
    ThreadPool::Observer workerObserver_;
    TaskSystem* host_ = nullptr;
    long long steps_ = 0;
    int failures_ = 0;
    std::string firstFailure_;
};

}  // namespace cloth
