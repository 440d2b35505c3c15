#include "engine/flag/flag.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "engine/scene/config_error.h"
#include "engine/profile/profiler.h"

namespace engine {

cloth::FlagDesc flagDescOf(const SceneConfig& scene) {
    const auto& f = scene.flag;
    // With contact, the sleeve on the pole's shell (no pinned edge through the pole).
    return {f.nx, f.ny, f.width, f.height, f.mass, f.stiffness, f.contact.enabled && (scene.subsystems & kCollision)};
}

cloth::ClothSettings clothSettingsOf(const SceneConfig& scene) {
    cloth::ClothSettings s;
    s.solver = scene.flag.solver;
    s.constraints = scene.flag.constraints;
    s.environment.drag = scene.flag.drag;
    s.air = scene.subsystems & kAir;
    s.airParams = scene.air;
    s.implicitAir = scene.flag.implicitAir;
    s.collisions = scene.subsystems & kCollision;
    s.thickness = scene.flag.thickness;
    s.substeps = scene.flag.substeps;
    s.contact = scene.flag.contact;
    s.contact.enabled = scene.flag.contact.enabled && (scene.subsystems & kCollision);
    return s;
}

namespace {

cloth::ClothDesc flagOnPoleOf(const SceneConfig& scene, const PoleMount& mount) {
    try {
        return cloth::flagOnPole(flagDescOf(scene), mount, scene.flag.thickness);
    } catch (const std::invalid_argument& e) {
        throw ConfigError(scene.file + ": flag: " + e.what());
    }
}

}  // namespace

cloth::Cloth makeFlagCloth(const SceneConfig& scene, const PoleMount& mount, const RigidFrame& carrier,
                           const std::vector<cloth::Collider>& solids) {
    cloth::ClothDesc desc = flagOnPoleOf(scene, mount);
    desc.solids.insert(desc.solids.end(), solids.begin(), solids.end());
    try {
        return cloth::Cloth(std::move(desc), clothSettingsOf(scene), carrier);
    } catch (const std::invalid_argument& e) {
        throw ConfigError(scene.file + ": flag." + e.what());
    }
}

Flag::Flag(const SceneConfig& scene, const PoleMount& mount, const RigidFrame& carrier,
           const std::vector<cloth::Collider>& solids)
    : mount_(mount), cloth_(makeFlagCloth(scene, mount, carrier, solids)) {}

void Flag::reconfigure(const SceneConfig& scene) {
    cloth::Model model = flagOnPoleOf(scene, mount_).model;
    if (model.particleCount() != cloth_.model().particleCount())
        throw ConfigError(scene.file + ": flag.resolution: a running flag keeps its particles");
    try {
        cloth_.reconfigure(clothSettingsOf(scene), &model);
    } catch (const std::invalid_argument& e) {
        throw ConfigError(scene.file + ": flag." + e.what());
    }
}

void Flag::tick(double h, const RigidFrame& carrier, const std::vector<cloth::Collider>& colliders) {
    cloth_.step(h, carrier, colliders);
    const cloth::ClothProfile& p = cloth_.profile();
    timings_.air += p.air;
    timings_.forces += p.forces;
    timings_.solve += p.solve;
    timings_.collision += p.collision;
    timings_.contact += p.contact;
}

void Flag::setTrace(Trace* trace) {
    trace_ = trace;
    if (trace) traceNames_ = {trace->nameId(phaseName(Phase::Air)), trace->nameId(phaseName(Phase::ClothForces)),
                              trace->nameId(phaseName(Phase::ClothSolve)), trace->nameId(phaseName(Phase::Collision)),
                              trace->nameId(phaseName(Phase::Contact)), trace->nameId("cloth_step")};
    cloth_.setObserver(trace ? this : nullptr);
    observeWorkers();
}

// The solver's pool tells when its workers ran; they become events on their own rows, named
// after the stage that split the work (air, cloth_step, collision).
void Flag::observeWorkers() {
    if (!trace_) {
        cloth_.setWorkerObserver(nullptr);
        return;
    }
    cloth_.setWorkerObserver([this](int worker, Trace::Clock::time_point b, Trace::Clock::time_point e) {
        trace_->complete(stage_, Trace::Category::Worker, b, e, -1, worker);
    });
}

void Flag::stageBegins(cloth::ClothStage stage) {
    switch (stage) {
        case cloth::ClothStage::Air: stage_ = traceNames_.air; break;
        case cloth::ClothStage::Solve: stage_ = traceNames_.step; break;
        case cloth::ClothStage::Collision: stage_ = traceNames_.collision; break;
        case cloth::ClothStage::Contact: stage_ = traceNames_.contact; break;
    }
}

void Flag::stageEnded(cloth::ClothStage stage, Clock::time_point begin, Clock::time_point end) {
    switch (stage) {
        case cloth::ClothStage::Air: trace_->complete(traceNames_.air, Trace::Category::Phase, begin, end); break;
        case cloth::ClothStage::Solve: traceStep(begin, end); break;
        case cloth::ClothStage::Collision:
            trace_->complete(traceNames_.collision, Trace::Category::Phase, begin, end);
            break;
        case cloth::ClothStage::Contact: trace_->complete(traceNames_.contact, Trace::Category::Phase, begin, end); break;
    }
}

// The forces from the step's start, the solve (with the integration after it) up to its end;
// neither leaves the span, and they never overlap (the solver timed them inside it, one after
// the other).
void Flag::traceStep(Trace::Clock::time_point begin, Trace::Clock::time_point end) const {
    using Clock = Trace::Clock;
    auto span = [](double ms) {
        return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
    };
    const cloth::StepProfile& p = cloth_.solver().profile();
    const Clock::time_point forcesEnd = std::min(begin + span(p.forcesMs), end);
    const Clock::time_point solveBegin = std::max(end - span(p.solveMs + p.integrateMs), forcesEnd);
    trace_->complete(traceNames_.forces, Trace::Category::Phase, begin, forcesEnd);
    trace_->complete(traceNames_.solve, Trace::Category::Phase, solveBegin, end);
}

}  // namespace engine
