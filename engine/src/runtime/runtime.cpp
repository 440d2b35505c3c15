#include "engine/runtime.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

#include "engine/config_error.h"
#include "engine/input_script.h"
#include "engine/tick_clock.h"
#include "runtime/runtime_impl.h"
#include "runtime/summary.h"

namespace engine {

namespace {

std::atomic<bool> gStop{false};
SubsystemCounters gCounters;

void onStopSignal(int) { gStop = true; }

}  // namespace

// Bullet worlds and GL contexts are counted where they are really constructed.
SubsystemCounters subsystemCounters() {
    SubsystemCounters c = gCounters;
    c.bulletWorlds = VehicleSystem::worldsCreated();
    c.glContexts = SceneView::contextsCreated();
    return c;
}
void installStopHandlers() {
    std::signal(SIGINT, onStopSignal);
    std::signal(SIGTERM, onStopSignal);
}
bool stopRequested() { return gStop.load(); }

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

// What the panel shows of the frame just finished.
void Runtime::Impl::endFrame() {
    if (!view || !view->hasPanel()) return;
    lastRow = profiler.rows().back();
    if (flag) {
        lastCounts = flag->solverCounts();
        lastSteps = flag->steps();
    }
}

// One fixed tick: the vehicle first, then the flag against the carrier's pose at the end of that
// tick, each timed in its own phase ("bullet" here, the cloth phases from the flag's timings).
void Runtime::Impl::tick() {
    double h = clock->tickDt();
    if (vehicle) {
        Profiler::Scope scope(profiler, ph.bullet);
        h = vehicle->stepTick(h);  // the flag steps exactly as long as the chassis did
    }
    if (flag) stepFlag(h);
    clock->countTick();
    if (flag) measurePinError();
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
    for (std::size_t r = 0; r < pins.size(); ++r) {
        const Eigen::Vector3d local = mount.base + Eigen::Vector3d(0, mount.height - r * dy, 0);
        maxPinError = std::max(maxPinError, (flag->state().x.col(pins[r].particle) - c.point(local)).norm());
    }
}

namespace {

// Makes --out's folder, refusing a non-empty one unless --force, which clears an earlier run's
// outputs from it.
void prepareOutDir(const RunOptions& options) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(options.outDir, ec) && !fs::is_empty(options.outDir, ec) && !options.force)
        throw ConfigError("--out " + options.outDir +
                          ": folder exists and is not empty (use --force to write into it)");
    if (options.force) {
        // --force replaces an earlier recording: remove what a run writes (and only that),
        // so the folder never mixes two runs' frames.
        for (const char* f : {"profile.csv", "summary.json", "video.mp4"}) fs::remove(fs::path(options.outDir) / f, ec);
        if (fs::is_directory(fs::path(options.outDir) / "frames", ec))
            for (const auto& e : fs::directory_iterator(fs::path(options.outDir) / "frames", ec))
                if (e.path().filename().string().rfind("frame_", 0) == 0) fs::remove(e.path(), ec);
    }
    fs::create_directories(options.outDir, ec);
    if (ec) throw ConfigError("--out " + options.outDir + ": cannot create folder: " + ec.message());
}

// Refuses a --trace path that cannot be written at the end of the run: a folder, or a file in a
// folder that does not exist.
void checkTracePath(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw ConfigError("--trace " + path + ": is a folder, not a file");
    const fs::path folder = fs::path(path).parent_path();
    if (!folder.empty() && !fs::is_directory(folder, ec))
        throw ConfigError("--trace " + path + ": folder " + folder.string() + " does not exist");
}

}  // namespace

// Applies the command line to the scene (frame size, window, recording) and rejects what cannot run.
void Runtime::Impl::applyOptions() {
    SceneConfig& s = scene;
    const RunOptions& options = opt;
    if (options.width) s.render.width = options.width;
    if (options.height) s.render.height = options.height;
    if (options.msaa >= 0) s.render.msaa = options.msaa;
    if ((s.render.width % 2) || (s.render.height % 2))
        throw ConfigError("--width/--height: " + std::to_string(s.render.width) + "x" +
                          std::to_string(s.render.height) + " must both be even");
    if (options.window) {
        if (!(s.subsystems & kRender))
            throw ConfigError(s.file + ": scene '" + s.name + "' does not render (no 'render' "
                              "subsystem), so --window has nothing to show");
        s.subsystems |= kWindow;
    }
    if ((options.video || !options.outDir.empty()) && !(s.subsystems & kRender))
        std::fprintf(stderr, "flagsim: note: scene '%s' does not render: %s gets the profile and summary only\n",
                     s.name.c_str(), options.outDir.empty() ? "(no --out)" : options.outDir.c_str());
    if (options.outDir.empty()) s.subsystems &= ~kRecording;
    if (options.noFrames && !options.video) s.subsystems &= ~kRecording;
    if (!options.recordInput.empty() && !(s.subsystems & kVehicle))
        throw ConfigError("--record-input: scene '" + s.name + "' has no vehicle to drive");
}

// Sets the frame count and the tick clock: whether the run advances in lockstep.
void Runtime::Impl::planFrames() {
    const SceneConfig& s = scene;
    const double duration = opt.duration > 0 ? opt.duration : s.duration;
    frames = opt.frames > 0 ? opt.frames : std::max(1, int(std::lround(duration * s.fps)));
    // Only live input (a window driving a vehicle without a script) follows the wall clock;
    // everything else, and any run that records its input, advances in lockstep.
    const bool liveInput = (s.subsystems & kWindow) && (s.subsystems & kVehicle) && opt.scriptPath.empty();
    const bool lockstep = !liveInput || !opt.recordInput.empty();
    clock.emplace(s.physicsHz, s.fps, s.maxTicksPerFrame, lockstep);
}

// Adds the profiler's phases, in frame order, only for the subsystems the scene has.
void Runtime::Impl::addPhases() {
    const unsigned subsystems = scene.subsystems;
    Profiler& p = profiler;
    if (subsystems & kVehicle) {
        ph.input = p.addPhase("input");
        ph.bullet = p.addPhase("bullet");
    }
    if (subsystems & kCloth) {
        if (subsystems & kAir) ph.air = p.addPhase("air");
        ph.clothForces = p.addPhase("cloth_forces");
        ph.clothSolve = p.addPhase("cloth_solve");
        if (subsystems & kCollision) ph.collision = p.addPhase("collision");
    }
    if (subsystems & kRender) {
        ph.render = p.addPhase("render");
        ph.readback = p.addPhase("readback");
        if (opt.overlay) ph.overlay = p.addPhase("overlay");  // the panel drawn into the frames
        else if (subsystems & kWindow) ph.overlay = p.addPhase("panel");  // on screen only
    }
    if (subsystems & kRecording) ph.write = p.addPhase("write");
}

// Builds the vehicle and its input: a script, the keyboard, and a recorder if asked for.
void Runtime::Impl::buildVehicle() {
    const SceneConfig& s = scene;
    const std::string scriptPath = opt.scriptPath.empty() ? s.script : opt.scriptPath;
    // In a window the keyboard drives unless a script is named on the command line.
    const bool live = (s.subsystems & kWindow) && opt.scriptPath.empty();
    if (!scriptPath.empty() && !live) script = InputScript::load(scriptPath);
    if (!opt.recordInput.empty()) recorder.emplace();
    vehicle = std::make_unique<VehicleSystem>(s, &profiler);
}

// Builds the flag on its pole (on the vehicle, or fixed in the world) and the ground it can hit.
void Runtime::Impl::buildFlag() {
    const SceneConfig& s = scene;
    const RigidFrame pose = carrier();
    if (vehicle) mount = vehicle->poleMount();
    else {
        mount.base = Eigen::Vector3d(s.pole.base[0], s.pole.base[1], s.pole.base[2]);
        mount.height = s.pole.height;
        mount.radius = s.pole.radius;
        mount.trailing = Eigen::Vector3d::UnitX();
    }
    flag = std::make_unique<Flag>(s, mount, pose);
    flag->setTrace(trace.get());
    if (s.subsystems & kCollision) {
        cloth::Collider ground;  // the ground plane, y = 0
        ground.shape = cloth::Collider::Shape::Plane;
        ground.axis = Eigen::Vector3d::UnitY();
        staticColliders.push_back(ground);
    }
}

// Builds the view that renders the scene (and its window).
void Runtime::Impl::buildView() {
    view = std::make_unique<SceneView>(scene, opt, vehicle.get(), flag.get());
    if (scene.subsystems & kWindow) ++gCounters.windows;
}

// Builds the recording of the rendered frames: PNG frames, video, as the options ask.
void Runtime::Impl::buildRecording() {
    recording = std::make_unique<Recording>(scene, opt);
    ++gCounters.frameWriters;
}

Runtime::Runtime(const SceneConfig& sceneIn, const RunOptions& options)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.scene = sceneIn;
    m.opt = options;
    m.applyOptions();
    // Output folder: never silently overwritten.
    if (!options.outDir.empty()) prepareOutDir(options);
    if (!options.tracePath.empty()) {
        checkTracePath(options.tracePath);
        m.trace = std::make_unique<Trace>();
        m.profiler.setTrace(m.trace.get());
    }
    m.planFrames();
    m.addPhases();
    if (m.scene.subsystems & kVehicle) m.buildVehicle();
    else if (!options.scriptPath.empty()) m.script = InputScript::load(options.scriptPath);  // its events
    if (m.scene.subsystems & kCloth) m.buildFlag();
    if (m.scene.subsystems & kRender) m.buildView();
    if (m.view && m.view->hasPanel()) m.scenes = sceneNames(options.assetsDir);
    if (m.view && (m.scene.subsystems & kRecording)) m.buildRecording();
    m.clock->startWall();
}

Runtime::~Runtime() = default;

bool Runtime::frame() {
    Impl& m = *impl_;
    if (m.frame >= m.frames) return false;
    if (stopRequested()) {
        m.stopReason = "interrupted";
        return false;
    }
    if (m.view && m.view->windowClosed()) {
        m.stopReason = "window closed";
        return false;
    }
    if (!m.nextScene.empty()) {
        m.stopReason = "switched to " + m.nextScene;
        return false;
    }
    Profiler& p = m.profiler;
    p.beginFrame();
    if (m.ph.input >= 0) {
        Profiler::Scope scope(p, m.ph.input);
        m.readInput();
    } else {
        m.readInput();
    }

    // Fixed ticks this frame: exactly the schedule in lockstep, else what the wall clock gives;
    // none while paused, one for a single step.
    const long long ticksNow = m.ticksThisFrame();
    if (m.flag) m.flag->resetTimings();
    for (long long k = 0; k < ticksNow; ++k) m.tick();
    if (m.restartSchedule) m.clock->restartSchedule(m.simFrame);
    m.restartSchedule = false;
    if (m.flag) {
        const FlagTimings& ft = m.flag->timings();
        if (m.ph.air >= 0) p.add(m.ph.air, ft.air);
        p.add(m.ph.clothForces, ft.forces);
        p.add(m.ph.clothSolve, ft.solve);
        if (m.ph.collision >= 0) p.add(m.ph.collision, ft.collision);
    }

    if (m.view) {
        const std::optional<PanelState> panel =
            m.view->hasPanel() ? std::optional<PanelState>(m.panelState()) : std::nullopt;
        const double frameSeconds = m.lastRow.empty() ? 1.0 / m.scene.fps : m.lastRow.back() / 1000;
        m.view->renderFrame(p, m.ph.render, m.ph.readback, m.ph.overlay, panel ? &*panel : nullptr, frameSeconds);
    }
    if (m.recording) {
        Profiler::Scope scope(p, m.ph.write);
        m.recording->write(m.frame, m.view->pixels());
    }
    p.endFrame();
    m.endFrame();
    ++m.frame;
    if (m.view && m.view->hasWindow()) {  // a window shows frames at the frame rate
        m.nextFrame = std::max(m.nextFrame + std::chrono::duration_cast<Clock::duration>(
                                                 std::chrono::duration<double>(1.0 / m.scene.fps)),
                               Clock::now() - std::chrono::milliseconds(100));
        std::this_thread::sleep_until(m.nextFrame);
    }
    return true;
}

int Runtime::finish() {
    Impl& m = *impl_;
    int code = 0;
    RunFacts f;
    f.scene = m.scene.name;
    f.subsystems = describeSubsystems(m.scene.subsystems);
    f.solver = (m.scene.subsystems & kCloth) ? m.scene.flag.solver.describe() : "";
    f.script = m.script ? (m.opt.scriptPath.empty() ? m.scene.script : m.opt.scriptPath) : "";
    f.frames = m.frame;
    f.width = m.scene.render.width;
    f.height = m.scene.render.height;
    f.simTime = m.clock->simTime();
    f.wallSeconds = std::chrono::duration<double>(Clock::now() - m.start).count();
    f.stopReason = m.stopReason;
    f.maxPinError = m.maxPinError;
    if (m.flag) {
        f.clothSteps = m.flag->steps();
        const SolverCounts& counts = m.flag->solverCounts();
        const double steps = double(std::max<long long>(f.clothSteps, 1));
        f.iterationsMean = double(counts.iterations) / steps;
        f.linearIterationsMean = double(counts.linearIterations) / steps;
        f.iterationsMax = counts.maxIterations;
        f.clothFailures = m.flag->failures();
        f.firstClothFailure = m.flag->firstFailure();
    }
    if (m.recording) {
        std::string error;
        if (!m.recording->finish(&f.framesWritten, &f.video, &error)) {
            f.writerError = error;
            std::fprintf(stderr, "flagsim: error: %s\n", error.c_str());
            code = 1;
        }
    }
    if (m.recorder) {
        std::string error;
        if (!m.recorder->script().save(m.opt.recordInput, &error)) {
            std::fprintf(stderr, "flagsim: error: %s\n", error.c_str());
            code = 1;
        }
    }
    if (!m.opt.outDir.empty()) {
        std::string error;
        if (!m.profiler.writeCsv(m.opt.outDir + "/profile.csv", &error) ||
            !writeSummary(m.opt.outDir + "/summary.json", f, m.profiler, &error)) {
            std::fprintf(stderr, "flagsim: error: %s\n", error.c_str());
            code = 1;
        }
    }
    if (m.trace) {
        std::string error;
        if (!m.trace->write(m.opt.tracePath, &error)) {
            std::fprintf(stderr, "flagsim: error: --trace %s\n", error.c_str());
            code = 1;
        }
    }
    return code;
}

int Runtime::frameIndex() const { return impl_->frame; }
const SceneConfig& Runtime::scene() const { return impl_->scene; }
const std::string& Runtime::nextScene() const { return impl_->nextScene; }
std::optional<std::array<float, 4>> Runtime::widgetRect(const std::string& label) const {
    return impl_->view ? impl_->view->widgetRect(label) : std::nullopt;
}
int Runtime::frameCount() const { return impl_->frames; }
double Runtime::simTime() const { return impl_->clock->simTime(); }
const Profiler& Runtime::profiler() const { return impl_->profiler; }
const Flag* Runtime::flag() const { return impl_->flag.get(); }
Flag* Runtime::mutableFlag() { return impl_->flag.get(); }
double Runtime::maxPinError() const { return impl_->maxPinError; }
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

namespace {

void drawProgress(int done, int total, double wallSeconds) {
    const int width = 30;
    const int filled = total > 0 ? done * width / total : width;
    std::fprintf(stderr, "\r[%.*s%*s] %d/%d frames  %.1f frames/s ", filled,
                 "##############################", width - filled, "", done, total,
                 wallSeconds > 0 ? done / wallSeconds : 0.0);
    std::fflush(stderr);
}

}  // namespace

namespace {

// One run of one scene; *next is the scene the panel asked for (empty: none).
int runOnce(const SceneConfig& scene, const RunOptions& options, std::string* next) {
    Runtime rt(scene, options);
    const bool progress = !options.noProgress && isatty(fileno(stderr));
    const auto t0 = Clock::now();
    while (rt.frame())
        if (progress && (rt.frameIndex() % 10 == 0 || rt.frameIndex() == rt.frameCount()))
            drawProgress(rt.frameIndex(), rt.frameCount(),
                         std::chrono::duration<double>(Clock::now() - t0).count());
    if (progress) std::fprintf(stderr, "\n");
    int code = rt.finish();
    *next = rt.nextScene();
    std::printf("scene %s: %d frames, %.2f s simulated, %.2f s wall\n", scene.name.c_str(),
                rt.frameIndex(), rt.simTime(), std::chrono::duration<double>(Clock::now() - t0).count());
    if (rt.flag()) {
        std::printf("cloth: %lld steps, solver %s, max pin error %.3g m, %d failed steps\n",
                    rt.flag()->steps(), scene.flag.solver.describe().c_str(), rt.maxPinError(),
                    rt.flag()->failures());
        if (rt.flag()->failures())
            std::printf("cloth: first failure: %s\n", rt.flag()->firstFailure().c_str());
    }
    std::printf("%s", rt.profiler().summaryTable().c_str());
    if (!options.outDir.empty()) std::printf("recorded to %s\n", options.outDir.c_str());
    return code;
}

}  // namespace

int runScene(const SceneConfig& scene, const RunOptions& options) {
    installStopHandlers();
    std::string next;
    int code = runOnce(scene, options, &next);
    while (code == 0 && !next.empty() && !stopRequested()) {  // the panel switched scene or restarted
        SceneConfig chosen = loadScene(next);
        code = runOnce(chosen, options, &next);
    }
    if (stopRequested()) {
        std::printf("interrupted: outputs are complete up to the last frame\n");
        if (code == 0) code = 130;  // the shell's convention for a run ended by SIGINT
    }
    return code;
}

}  // namespace engine
