#pragma once
// The flag subsystem: a cloth from the scene's flag settings, its pole-side column pinned to a
// pole carried by a rigid frame (a vehicle chassis, or the world for a fixed pole), stepped by
// the scene's solver with air and collisions as the scene declares them.
//
// Recovery policy when a step fails (non-finite state or solver breakdown): the cloth library
// leaves the state as it was before the step; the flag retries the tick in 8 substeps of the same
// solver; if that fails too, it resets to its rest shape at the pole's current pose. Every
// failure is counted and the first is reported with its step number and particle.

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "cloth/air.h"
#include "cloth/collision.h"
#include "cloth/solver.h"
#include "engine/scene.h"
#include "engine/trace.h"

namespace engine {

// A rigid frame and its velocity: x_world = position + rotation * x_local.
struct RigidFrame {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d linearVelocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d point(const Eigen::Vector3d& local) const { return position + rotation * local; }
    Eigen::Vector3d velocityAt(const Eigen::Vector3d& world) const {
        return linearVelocity + angularVelocity.cross(world - position);
    }
};

// Where the pole stands in its carrier's frame: base point, height; the flag trails along
// `trailing` (a unit vector in the carrier frame, perpendicular to the pole's +y axis).
struct PoleMount {
    Eigen::Vector3d base = Eigen::Vector3d::Zero();
    double height = 3.0;
    double radius = 0.03;
    Eigen::Vector3d trailing = -Eigen::Vector3d::UnitZ();
};

struct FlagTimings {  // milliseconds, summed since the last reset
    double forces = 0, solve = 0, air = 0, collision = 0;
};

struct SolverCounts {  // the solver's iterations (StepResult), summed over the steps since construction
    long long iterations = 0;
    int maxIterations = 0;         // the most in one step
    long long linearIterations = 0;  // newton: GMRES iterations (StepResult::linearIterations)
};

class Flag {
public:
    // Throws ConfigError when the settings cannot make a cloth (the message names the field).
    Flag(const SceneConfig& scene, const PoleMount& mount, const RigidFrame& carrier);

    // One tick of length h with the carrier at its end-of-tick pose: pins follow the pole, air
    // and collisions as enabled. `colliders` are world-space (pole capsule, body, ground).
    void tick(double h, const RigidFrame& carrier, const std::vector<cloth::Collider>& colliders);

    const cloth::Model& model() const { return model_; }
    const cloth::State& state() const { return state_; }
    cloth::State& mutableState() { return state_; }  // tests inject faults through this
    // Moves the flag to `state` (a reference run's, for a restart) with the pins on `carrier`; the
    // solver forgets its history.
    void restart(const cloth::State& state, const RigidFrame& carrier);
    // Takes the scene's solver, constraints, stiffness, mass, drag and air, keeping the state (the
    // resolution must be the same). Throws ConfigError for a bad solver, leaving the flag as it was.
    void reconfigure(const SceneConfig& scene);
    // Back to rest on the pole at the carrier's pose (what a failed tick's recovery does).
    void reset(const RigidFrame& carrier) { resetToRest(carrier); }
    const SolverCounts& solverCounts() const { return counts_; }
    const std::vector<cloth::Pin>& pins() const { return pins_; }
    const FlagTimings& timings() const { return timings_; }
    // Each step's phases go to trace as events too (null: none), named as the runtime's profile
    // phases. The solver reports how long its forces and its solve took, not when: they are
    // placed at the start and at the end of the step's measured span, in the order they run.
    void setTrace(Trace* trace);
    void resetTimings() { timings_ = {}; }
    long long steps() const { return steps_; }
    int failures() const { return failures_; }
    const std::string& firstFailure() const { return firstFailure_; }
    // The world-space pole capsule for the given carrier pose.
    cloth::Collider poleCollider(const RigidFrame& carrier) const;

private:
    void updatePins(const RigidFrame& carrier);
    bool stepOnce(double h, const std::vector<cloth::Collider>& colliders);
    bool fail(const std::string& what, cloth::Index particle);  // counts a failed step; false
    void traceStep(Trace::Clock::time_point begin, Trace::Clock::time_point end) const;
    void resetToRest(const RigidFrame& carrier);
    void applySettings(const SceneConfig& scene);

    cloth::Model model_;
    cloth::State state_;
    std::unique_ptr<cloth::Solver> solver_;
    cloth::Environment env_;
    std::vector<cloth::Pin> pins_;
    std::vector<Eigen::Vector3d> pinLocal_;  // pinned particles in the carrier frame
    std::vector<std::uint8_t> collisionSkip_;  // pinned, or inside the pole at rest (the sleeve)
    cloth::AirWorkspace airWorkspace_;          // scratch of the air and the collisions, reused every tick
    cloth::CollisionWorkspace collisionWorkspace_;
    PoleMount mount_;
    bool air_ = false, collision_ = false, implicitAir_ = true;
    cloth::AirParams airParams_;
    double thickness_ = 0;
    int substeps_ = 1;
    // A step that leaves a particle farther from the pole than this many flag diagonals has
    // diverged (a failure, like a non-finite one).
    static constexpr double kRunawayReach = 10;
    double reach_ = 0;
    cloth::Points airForce_;
    std::vector<cloth::Mat3> airJacobian_, airDamping_;
    FlagTimings timings_;
    SolverCounts counts_;
    Trace* trace_ = nullptr;
    struct TraceNames {
        int air = -1, forces = -1, solve = -1, collision = -1, step = -1;
    } traceNames_;
    int stage_ = -1;  // the trace name of what the solver's pool works on now (its workers' events)
    void observeWorkers();
    long long steps_ = 0;
    int failures_ = 0;
    std::string firstFailure_;
};

}  // namespace engine
