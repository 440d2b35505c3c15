// The frame loop: input and commands, the fixed ticks (the vehicle, then the flag against the
// carrier's pose), the view's render and readback, the recording; each in its profile phase.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "runtime/runtime_impl.h"

namespace engine {

// The window's events (the panel's too), the commands of this frame, then the actions: the
// window's when it drives live, else the script's at this frame's time.
void Runtime::Impl::readInput() {
    Actions polled;
    if (view) polled = view->pollActions();  // also keeps a window responsive
    applyCommands();
    if (!vehicle) return;
    const double t = clock->simTime();
    actions = (view && view->hasWindow() && !script) ? polled : script ? script->sample(t) : Actions{};
    if (recorder) recorder->record(t, actions);
    vehicle->setActions(actions);
}

// What the panel shows of the frame just finished: the solver's counts since (its phases are
// the profiler's last frame).
void Runtime::Impl::endFrame() {
    if (!view || !view->hasPanel() || !flag) return;
    lastCounts = flag->solverCounts();
    lastSteps = flag->steps();
}

// One fixed tick: the vehicle first, then the flag against the carrier's pose at the end of that
// tick, each timed in its own phase ("bullet" here, the cloth phases from the flag's timings).
void Runtime::Impl::tick() {
    double h = clock->tickDt();
    if (vehicle) {
        Profiler::Scope scope(profiler, Phase::Bullet);
        h = vehicle->stepTick(h);  // the flag steps exactly as long as the chassis did
    }
    if (flag) stepFlag(h);
    clock->countTick();
    if (flag) measurePinError();
    if (opt.crossingsEveryTick) countCrossings();
}

// The flag's crossings now, with the carrier and the vehicle's body where they are.
void Runtime::Impl::countCrossings() {
    if (!crossings) return;
    Profiler::Scope scope(profiler, Phase::Crossings);
    const cloth::Collider body = vehicle ? vehicle->bodyCollider() : cloth::Collider{};
    crossings->count(*flag, carrier(), vehicle ? &body : nullptr);
}

// Steps the flag by h with its pole where the carrier is now, against the ground and, on a
// vehicle with collisions, the pole and the vehicle's body.
void Runtime::Impl::stepFlag(double h) {
    const RigidFrame c = carrier();
    std::vector<cloth::Collider> colliders = staticColliders;
    if (!vehicle) colliders.push_back(flag->poleCollider(c));
    else if (scene.subsystems & kCollision) {
        colliders.push_back(flag->poleCollider(c));
        colliders.push_back(vehicle->bodyCollider());
    }
    flag->tick(h, c, colliders);
}

// Pin error: each pinned particle against its point on the pole, computed here from the mount
// and the carrier's pose (not from the flag's own pin targets).
void Runtime::Impl::measurePinError() {
    const RigidFrame c = carrier();
    const auto& pins = flag->pins();
    const double dy = scene.flag.height / (scene.flag.ny - 1);
    // With contact the pinned column sits on the pole's collision shell (cloth/flag_on_pole.h).
    const double sleeve = flagDescOf(scene).onShell ? mount.radius + scene.flag.thickness : 0;
    for (std::size_t r = 0; r < pins.size(); ++r) {
        const Eigen::Vector3d local = mount.base + Eigen::Vector3d(0, mount.height - r * dy, 0) + sleeve * mount.trailing;
        maxPinError = std::max(maxPinError, (flag->state().x.col(pins[r].particle) - c.point(local)).norm());
    }
}

// Why the run ends before this frame, or empty.
std::string Runtime::Impl::stopBefore() const {
    if (frame >= frames) return stopReason;
    if (stopRequested()) return "interrupted";
    if (view && view->windowClosed()) return "window closed";
    if (!nextScene.empty()) return "switched to " + nextScene;
    return {};
}

// This frame's fixed ticks: exactly the schedule in lockstep, else what the wall clock gives;
// none while paused, one for a single step. The flag's phases come from its timings.
void Runtime::Impl::stepPhysics() {
    const long long ticksNow = ticksThisFrame();
    if (flag) flag->resetTimings();
    for (long long k = 0; k < ticksNow; ++k) tick();
    if (ticksNow > 0 && !opt.crossingsEveryTick) countCrossings();  // the state the frame shows
    if (restartSchedule) clock->restartSchedule(simFrame);
    restartSchedule = false;
    if (!flag) return;
    const FlagTimings& ft = flag->timings();
    profiler.add(Phase::Air, ft.air);
    profiler.add(Phase::ClothForces, ft.forces);
    profiler.add(Phase::ClothSolve, ft.solve);
    profiler.add(Phase::Collision, ft.collision);
    profiler.add(Phase::Contact, ft.contact);
}

// The view draws the frame (and the panel), the recording writes it.
void Runtime::Impl::renderAndRecord() {
    if (view) {
        const std::optional<PanelState> panel = view->hasPanel() ? std::optional<PanelState>(panelState()) : std::nullopt;
        const double frameSeconds = profiler.frameCount() == 0 ? 1.0 / scene.fps : profiler.lastFrame().frame / 1000;
        view->renderFrame(profiler, panel ? &*panel : nullptr, frameSeconds);
    }
    if (recording) {
        Profiler::Scope scope(profiler, Phase::Write);
        recording->write(frame, view->pixels());
    }
}

// --export-mesh: the flag's state at the end of this frame's ticks (what was rendered), in its
// own phase.
void Runtime::Impl::exportMesh() {
    if (!meshExport) return;
    Profiler::Scope scope(profiler, Phase::ExportMesh);
    char time[40];
    std::snprintf(time, sizeof time, "%.17g", clock->simTime());
    const std::string comment = "flagsim scene " + scene.name + " frame " + std::to_string(frame) + " time " + time +
                                " s solver " + cloth::describe(scene.flag.solver);
    meshExport->write(frame, comment, flag->state().x, flag->model().triangles());
}

// A window shows frames at the frame rate.
void Runtime::Impl::pace() {
    if (!view || !view->hasWindow()) return;
    nextFrame = std::max(nextFrame + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / scene.fps)),
                         Clock::now() - std::chrono::milliseconds(100));
    std::this_thread::sleep_until(nextFrame);
}

bool Runtime::frame() {
    Impl& m = *impl_;
    if (const std::string why = m.stopBefore(); !why.empty()) {
        m.stopReason = why;
        return false;
    }
    m.profiler.beginFrame();
    {
        Profiler::Scope scope(m.profiler, Phase::Input);
        m.readInput();
    }
    m.stepPhysics();
    m.renderAndRecord();
    m.exportMesh();
    m.profiler.endFrame();
    m.endFrame();
    ++m.frame;
    m.pace();
    return true;
}

int Runtime::frameIndex() const { return impl_->frame; }
const SceneConfig& Runtime::scene() const { return impl_->scene; }
const std::string& Runtime::nextScene() const { return impl_->nextScene; }
std::optional<std::array<float, 4>> Runtime::widgetRect(const std::string& label) const {
    return impl_->view ? impl_->view->widgetRect(label) : std::nullopt;
}
std::vector<std::string> Runtime::widgetLabels() const {
    return impl_->view ? impl_->view->widgetLabels() : std::vector<std::string>{};
}
int Runtime::refusals() const { return impl_->refusals; }
int Runtime::frameCount() const { return impl_->frames; }
double Runtime::simTime() const { return impl_->clock->simTime(); }
const Profiler& Runtime::profiler() const { return impl_->profiler; }
const Flag* Runtime::flag() const { return impl_->flag.get(); }
Flag* Runtime::mutableFlag() { return impl_->flag.get(); }
double Runtime::maxPinError() const { return impl_->maxPinError; }
cloth::CrossingCounts Runtime::mostCrossings() const {
    return impl_->crossings ? impl_->crossings->tally().most : cloth::CrossingCounts{};
}
const std::vector<std::uint8_t>& Runtime::pixels() const {
    static const std::vector<std::uint8_t> none;
    return impl_->view ? impl_->view->pixels() : none;
}
Eigen::Vector3d Runtime::poleTop() const {
    if (impl_->vehicle) {
        const PoleMount mount = impl_->vehicle->poleMount();
        return impl_->vehicle->carrier().point(mount.base + Eigen::Vector3d(0, mount.height, 0));
    }
    const auto& b = impl_->scene.pole.base;
    return Eigen::Vector3d(b[0], b[1] + impl_->scene.pole.height, b[2]);
}
Eigen::Vector3d Runtime::carrierVelocity() const { return impl_->carrier().linearVelocity; }

}  // namespace engine
