// Commands in the running scene: the script's events and the panel's requests, applied at the
// start of a frame and recorded with its index; pause and single steps; what the panel shows.

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "cloth/diagnostics.h"
#include "engine/scene/config_error.h"
#include "runtime/runtime_impl.h"

namespace engine {

void Runtime::Impl::applyCommands() {
    std::vector<Command> commands;
    if (script) commands = script->commandsAt(frame);
    if (view) {
        PanelRequests r = view->takeRequests();
        commands.insert(commands.end(), r.commands.begin(), r.commands.end());
        if (!r.scene.empty()) nextScene = resolveScenePath(r.scene, opt.assetsDir);
        if (r.restart) nextScene = scene.file;
        for (const std::string& why : r.refusals) refuse(why);
    }
    for (const Command& c : commands) {
        apply(c);
        // A command that no scene could take (a value out of range) is left out of the recording,
        // whose loader would refuse it; one this scene refused (a solver's keys in conflict)
        // stays, and is refused again in the replay.
        if (recorder && checkCommand(c).empty()) recorder->record(frame, c);
    }
}

namespace {

// The flag setting a command changes, in a copy of the scene (apply() has taken every other command).
void changeFlagSettings(SceneConfig& s, const Command& c) {
    if (c.name == "solver") {
        std::string error;
        if (!cloth::parseSolverConfig(c.value, s.flag.solver, &error)) throw ConfigError(error);
    } else if (c.name == "stretch") s.flag.stiffness.structural = commandNumber(c);
    else if (c.name == "shear") s.flag.stiffness.shear = commandNumber(c);
    else if (c.name == "bend") s.flag.stiffness.bend = commandNumber(c);
    else if (c.name == "mass") s.flag.mass = commandNumber(c);
    else if (c.name == "air_density") s.air.density = commandNumber(c);
    else if (c.name == "wind") {
        const std::vector<double> w = commandVector(c);
        s.air.wind = cloth::Vec3(w[0], w[1], w[2]);
    }
}

}  // namespace

// A command the scene cannot take (a solver whose keys conflict, a flag setting in a scene
// without a flag) is refused with a message, and the run goes on as it was, in a replay too.
void Runtime::Impl::apply(const Command& c) {
    const std::string why = checkCommand(c);
    if (!why.empty()) return refuse(why);
    if (c.name == "pause") {
        paused = c.value == "on";
        if (!paused) clock->startWall();  // the paused wall time is not owed as ticks
    } else if (c.name == "step") {
        stepPending = paused;
    } else if (c.name == "camera") {
        const std::vector<double> o = commandVector(c);
        if (view) view->setOrbit(o[0], o[1], o[2]);
    } else if (c.name == "physics_hz") {
        scene.physicsHz = commandNumber(c);
        clock->setPhysicsHz(scene.physicsHz, simFrame);
    } else if (c.name == "reset") {
        if (flag) flag->reset(carrier());
    } else if (flag) {
        SceneConfig next = scene;
        try {
            changeFlagSettings(next, c);
            flag->reconfigure(next);
            scene = next;
        } catch (const ConfigError& e) {
            refuse("command " + c.name + " " + c.value + " refused: " + e.what());
        }
    } else {
        refuse("command " + c.name + ": scene '" + scene.name + "' has no flag");
    }
}

// A refused command leaves the run as it was; the user sees why on stderr and in the panel.
void Runtime::Impl::refuse(const std::string& why) {
    std::fprintf(stderr, "flagsim: frame %d: %s\n", frame, why.c_str());
    ++refusals;
    lastRefusal = why;
}

// The ticks this frame runs: the schedule's, none while paused, one for a single step (after
// which the schedule goes on from the ticks reached: restartSchedule).
long long Runtime::Impl::ticksThisFrame() {
    if (!paused) return clock->ticksDue(simFrame++);
    restartSchedule = stepPending;
    stepPending = false;
    return restartSchedule ? 1 : 0;
}

std::vector<std::string> sceneNames(const std::string& assetsDir) {
    namespace fs = std::filesystem;
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(assetsDir) / "scenes", ec))
        if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

PanelState Runtime::Impl::panelState() const {
    PanelState s;
    s.scene = scene.name;
    s.refusal = lastRefusal;
    s.antiAliasing = view ? view->antiAliasing() : "off";
    s.scenes = scenes;
    if (recorder || recording || meshExport) s.switchNote = "recording: one run of one scene (no switching)";
    s.hasFlag = flag != nullptr;
    s.hasAir = scene.subsystems & kAir;
    s.solver = scene.flag.solver;
    s.stiffness = scene.flag.stiffness;
    s.mass = scene.flag.mass;
    s.wind = scene.air.wind;
    s.airDensity = scene.air.density;
    s.physicsHz = clock->physicsHz();
    s.paused = paused;
    s.simTime = clock->simTime();
    // The last frame's phases and its whole.
    s.phases = profiler.phases();
    if (profiler.frameCount() > 0) {
        const FrameProfile& last = profiler.lastFrame();
        for (int p = 0; p < kPhaseCount; ++p)
            if (profiler.enabled(Phase(p))) s.phaseMs.push_back(last[Phase(p)]);
        s.phaseMs.push_back(last.frame);
    }
    s.phases.push_back("frame");
    if (flag) {
        const cloth::Diagnostics d = cloth::measure(flag->model(), cloth::Environment{}, flag->state());
        s.p99Stretch = d.p99Stretch;
        s.maxStretch = d.maxStretch;
        const long long steps = flag->steps() - lastSteps;
        s.iterationsPerStep = steps > 0 ? double(flag->solverCounts().iterations - lastCounts.iterations) / steps : 0;
    }
    if (crossings) s.crossings = crossings->tally().last, s.crossingsMax = crossings->tally().max;
    return s;
}

}  // namespace engine
