// Building the runtime: the command line applied to the scene, the frame plan, the profile's
// phases, and only the subsystems the scene declares (vehicle, flag, view, recording).

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "engine/scene/config_error.h"
#include "engine/scene/input_script.h"
#include "runtime/runtime_impl.h"

namespace engine {

namespace {

SubsystemCounters gCounters;

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

// Makes --export-mesh's folder (its parent must exist), refusing a file, a folder this process
// cannot write into, and a non-empty folder unless --force, which removes an earlier run's meshes
// (and only those) so the folder never mixes two runs.
void prepareMeshDir(const std::string& dir, bool force) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const std::string option = "--export-mesh " + dir + ": ";
    fs::path path(dir);
    if (!path.has_filename()) path = path.parent_path();  // "meshes/" is the folder "meshes"
    if (fs::exists(path, ec) && !fs::is_directory(path, ec)) throw ConfigError(option + "is a file, not a folder");
    if (!fs::exists(path, ec)) {
        const fs::path folder = path.parent_path();
        if (!folder.empty() && !fs::is_directory(folder, ec))
            throw ConfigError(option + "folder " + folder.string() + " does not exist");
        fs::create_directory(path, ec);
        if (ec) throw ConfigError(option + "cannot create folder: " + ec.message());
    } else if (!fs::is_empty(path, ec) && !force) {
        throw ConfigError(option + "folder exists and is not empty (use --force to write into it)");
    } else if (force) {
        for (const auto& e : fs::directory_iterator(path, ec)) {
            const std::string name = e.path().filename().string();
            const bool mesh = name.size() > 5 && name.rfind("flag_", 0) == 0 &&
                              (name.ends_with(".obj") || name.ends_with(".obj.tmp"));
            if (mesh) fs::remove(e.path(), ec);
        }
    }
    if (access(path.c_str(), W_OK | X_OK) != 0)
        throw ConfigError(option + "cannot write into folder: " + std::strerror(errno));
}

}  // namespace

// Bullet worlds and GL contexts are counted where they are really constructed.
SubsystemCounters subsystemCounters() {
    SubsystemCounters c = gCounters;
    c.bulletWorlds = VehicleSystem::worldsCreated();
    c.glContexts = SceneView::contextsCreated();
    return c;
}

// Applies the command line to the scene (frame size, window, recording) and rejects what cannot run.
void Runtime::Impl::applyOptions() {
    SceneConfig& s = scene;
    const RunOptions& options = opt;
    if (options.width) s.render.width = options.width;
    if (options.height) s.render.height = options.height;
    // --msaa N: N samples, and unless --aa says otherwise multisampling (N > 1) or none.
    if (options.msaa >= 0) {
        s.render.msaa = options.msaa;
        s.render.aa = options.msaa > 1 ? AntiAliasing::Msaa : AntiAliasing::Off;
    }
    if (!options.aa.empty() && !antiAliasingOf(options.aa, s.render.aa))
        throw ConfigError("--aa " + options.aa + ": must be one of: auto, off, msaa, post");
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
    if (!options.exportMeshDir.empty() && !(s.subsystems & kCloth))
        throw ConfigError("--export-mesh " + options.exportMeshDir + ": scene '" + s.name +
                          "' has no cloth (no 'cloth' subsystem), so there is no mesh to export");
    if (options.outDir.empty()) s.subsystems &= ~kRecording;
    if (options.noFrames && !options.video) s.subsystems &= ~kRecording;
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

// Enables the profile's phases of the subsystems the scene has (the others are never timed).
void Runtime::Impl::enablePhases() {
    const unsigned subsystems = scene.subsystems;
    Profiler& p = profiler;
    if (subsystems & kVehicle) {
        p.enable(Phase::Input);
        p.enable(Phase::Bullet);
    }
    if (subsystems & kCloth) {
        if (subsystems & kAir) p.enable(Phase::Air);
        p.enable(Phase::ClothForces);
        p.enable(Phase::ClothSolve);
        if (subsystems & kCollision) p.enable(Phase::Collision);
        if ((subsystems & kCollision) && scene.flag.contact.enabled) p.enable(Phase::Contact);
        if (subsystems & kCollision) p.enable(Phase::Crossings);
    }
    if (subsystems & kRender) {
        p.enable(Phase::Render);
        p.enable(Phase::Readback);
        if (opt.overlay) p.enable(Phase::Overlay);            // the panel drawn into the frames
        else if (subsystems & kWindow) p.enable(Phase::Panel);  // on screen only
    }
    if (subsystems & kRecording) p.enable(Phase::Write);
    if (!opt.exportMeshDir.empty()) p.enable(Phase::ExportMesh);
}

// Builds the vehicle and its input: a script or the keyboard.
void Runtime::Impl::buildVehicle() {
    const SceneConfig& s = scene;
    const std::string scriptPath = opt.scriptPath.empty() ? s.script : opt.scriptPath;
    // In a window the keyboard drives unless a script is named on the command line.
    const bool live = (s.subsystems & kWindow) && opt.scriptPath.empty();
    if (!scriptPath.empty() && !live) script = InputScript::load(scriptPath);
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
    std::vector<cloth::Collider> solids;  // the vehicle's body, beside the pole
    if (vehicle && (s.subsystems & kCollision)) solids.push_back(vehicle->bodySolid());
    flag = std::make_unique<Flag>(s, mount, pose, solids);
    if (s.subsystems & kCollision) crossings = std::make_unique<CrossingWatch>(s, mount, true);
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
    else m.profiler.setRowLimit(kLiveProfileRows);  // no profile.csv: memory bounded in a long session
    if (!options.tracePath.empty()) {
        checkTracePath(options.tracePath);
        m.trace = std::make_unique<Trace>();
        m.profiler.setTrace(m.trace.get());
    }
    if (!options.exportMeshDir.empty()) {  // after --out's folder, which may hold this one
        prepareMeshDir(options.exportMeshDir, options.force);
        m.meshExport = std::make_unique<MeshExport>(options.exportMeshDir);
    }
    m.planFrames();
    m.enablePhases();
    if (!options.recordInput.empty()) m.recorder.emplace();  // the actions (with a vehicle) and the commands
    if (m.scene.subsystems & kVehicle) m.buildVehicle();
    else if (!options.scriptPath.empty()) m.script = InputScript::load(options.scriptPath);  // its events
    if (m.scene.subsystems & kCloth) m.buildFlag();
    if (m.scene.subsystems & kRender) m.buildView();
    if (m.view && m.view->antiAliasing().rfind("post", 0) == 0) m.profiler.enable(Phase::AntiAlias);
    if (m.view && m.view->hasPanel()) m.scenes = sceneNames(options.assetsDir);
    if (m.view && (m.scene.subsystems & kRecording)) m.buildRecording();
    m.clock->startWall();
}

Runtime::~Runtime() = default;
}  // namespace engine
