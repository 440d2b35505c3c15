#pragma once
// The scene's flag: a cloth::Cloth made from the scene's flag settings (cloth/flag_on_pole.h:
// column 0 attached along a pole on a rigid carrier, a vehicle's chassis or the world), stepped
// by the library with air and collisions as the scene declares them. What the engine adds: the
// scene's settings mapped onto the library's, its stages summed per frame for the profile, and
// each stage (and each worker's share of it) as an event of the trace.
//
// Recovery policy when a step fails (cloth/cloth.h): the tick again in 8x the substeps, then back
// to rest on the pole; every failure counted and the first reported with its step and particle.

#include <memory>
#include <string>
#include <vector>

#include "cloth/cloth.h"
#include "cloth/flag_on_pole.h"
#include "engine/scene/scene.h"
#include "engine/profile/trace.h"

namespace engine {

using RigidFrame = cloth::RigidFrame;
// Where the pole stands in its carrier's frame: base point, height, radius; the flag trails along
// `trailing` (a unit vector in the carrier frame, perpendicular to the pole's +y axis).
using PoleMount = cloth::Pole;

struct FlagTimings {  // milliseconds, summed since the last reset
    double forces = 0, solve = 0, air = 0, collision = 0, contact = 0;
};

using SolverCounts = cloth::ClothCounts;

// The library's flag and cloth settings from a scene's (throw ConfigError naming the scene file).
cloth::FlagDesc flagDescOf(const SceneConfig& scene);
cloth::ClothSettings clothSettingsOf(const SceneConfig& scene);
// The scene's flag as the library's cloth on `mount`, at rest on the carrier; `solids` the
// carrier's other solids in its frame (the vehicle's body), which contact keeps it out of.
cloth::Cloth makeFlagCloth(const SceneConfig& scene, const PoleMount& mount, const RigidFrame& carrier,
                           const std::vector<cloth::Collider>& solids = {});

class Flag : private cloth::ClothObserver {
public:
    // Throws ConfigError when the settings cannot make a cloth (the message names the field).
    Flag(const SceneConfig& scene, const PoleMount& mount, const RigidFrame& carrier,
         const std::vector<cloth::Collider>& solids = {});

    // One tick of length h with the carrier at its end-of-tick pose (Cloth::step). `colliders`
    // are world-space (pole capsule, body, ground).
    void tick(double h, const RigidFrame& carrier, const std::vector<cloth::Collider>& colliders);

    const cloth::Cloth& cloth() const { return cloth_; }
    const cloth::Model& model() const { return cloth_.model(); }
    const cloth::State& state() const { return cloth_.state(); }
    cloth::State& mutableState() { return cloth_.mutableState(); }  // tests inject faults through this
    // Moves the flag to `state` (a reference run's, for a restart) with the pins on `carrier`; the
    // solver forgets its history.
    void restart(const cloth::State& state, const RigidFrame& carrier) { cloth_.restart(state, carrier); }
    // Takes the scene's solver, constraints, stiffness, mass, drag and air, keeping the state (the
    // resolution must be the same). Throws ConfigError for a bad solver, leaving the flag as it was.
    void reconfigure(const SceneConfig& scene);
    // Back to rest on the pole at the carrier's pose (what a failed tick's recovery does).
    void reset(const RigidFrame& carrier) { cloth_.reset(carrier); }
    const SolverCounts& solverCounts() const { return cloth_.counts(); }
    const cloth::ContactReport& contactTotal() const { return cloth_.contactTotal(); }  // contact's work so far
    bool contactOn() const { return cloth_.settings().contact.enabled; }
    const std::vector<cloth::Pin>& pins() const { return cloth_.pins(); }
    const FlagTimings& timings() const { return timings_; }
    // Each step's stages go to trace as events too (null: none), named as the runtime's profile
    // phases. The solver reports how long its forces and its solve took, not when: they are
    // placed at the start and at the end of the step's measured span, in the order they run.
    void setTrace(Trace* trace);
    // A game's task system runs the solver's parallel work (cloth/task_system.h; null: the
    // solver's own threads), with the same bits; kept across reconfigure().
    void setTaskSystem(cloth::TaskSystem* host) { cloth_.setTaskSystem(host); }
    void resetTimings() { timings_ = {}; }
    long long steps() const { return cloth_.steps(); }
    int failures() const { return cloth_.failures(); }
    const std::string& firstFailure() const { return cloth_.firstFailure(); }
    // The world-space pole capsule for the given carrier pose.
    cloth::Collider poleCollider(const RigidFrame& carrier) const { return cloth::poleCollider(mount_, carrier); }

private:
    void stageBegins(cloth::ClothStage stage) override;
    void stageEnded(cloth::ClothStage stage, Clock::time_point begin, Clock::time_point end) override;
    void traceStep(Trace::Clock::time_point begin, Trace::Clock::time_point end) const;
    void observeWorkers();

    PoleMount mount_;
    cloth::Cloth cloth_;
    FlagTimings timings_;
    Trace* trace_ = nullptr;
    struct TraceNames {
        int air = -1, forces = -1, solve = -1, collision = -1, contact = -1, step = -1;
    } traceNames_;
    int stage_ = -1;  // the trace name of what the solver's pool works on now (its workers' events)
};

}  // namespace engine
