// flagsim: the demo. Runs a scene (by default the paper's showcase: a flag on a driven vehicle)
// with scripted or live input, renders headlessly or in a window, records frames, a video and a
// frame-time profile.
//
//   flagsim --scene flag_vehicle --script assets/scripts/drive.json --out out/demo --video

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "engine/scene/command.h"
#include "engine/scene/config_error.h"
#include "engine/runtime.h"
#include "engine/scene/scene.h"

int main(int argc, char** argv) {
    engine::RunOptions o;
    std::string scene = "flag_vehicle";
    std::string solver, constraints;
    bool setConstraints = false;
    CLI::App app{"flagsim: a cloth flag on a vehicle, stepped by Kang & Cho's solver."};
    // tools/run passes defaults first; what the user adds after them wins.
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.set_version_flag("--version", std::string("flagsim ") + FLAGSIM_VERSION);
    app.add_option("--scene", scene,
                   "scene name (flag_vehicle, flag_vehicle_hd, flag_vehicle_stiff, flag_vehicle_true_motion, "
                   "flag_vehicle_no_contact, hanging_flag, bench_cloth, vehicle_only) or a scene file path");
    app.add_option("--script", o.scriptPath, "input script (JSON); default: the scene's");
    app.add_option("--out", o.outDir,
                   "record into DIR: frames/frame_NNNNNN.png, profile.csv, summary.json");
    app.add_option("--frames", o.frames, "frames to run (default: the scene's duration)")
        ->check(CLI::Range(1, 10000000));
    app.add_option("--duration", o.duration, "simulated seconds to run (instead of --frames)")
        ->check(CLI::Range(0.001, 86400.0));
    app.add_flag("--video", o.video, "also encode DIR/video.mp4 (H.264, yuv420p) with ffmpeg");
    app.add_flag("--no-frames", o.noFrames, "with --out: do not write PNG frames");
    app.add_flag("--window", o.window, "show an SDL2 window with live keyboard/gamepad input");
    app.add_flag("--force", o.force, "allow writing into an existing output folder");
    app.add_option("--record-input", o.recordInput,
                   "write the actions actually applied as a script that replays to identical frames");
    app.add_option("--trace", o.tracePath,
                   "write the run as a Chrome Trace Event JSON file (frames, phases, Bullet's zones) "
                   "for Perfetto UI (ui.perfetto.dev) or chrome://tracing");
    app.add_option("--export-mesh", o.exportMeshDir,
                   "write the flag's mesh after every frame as DIR/flag_NNNNNN.obj (Wavefront OBJ, world "
                   "coordinates, exact to the bit; scenes with a cloth only)");
    app.add_flag("--crossings-every-tick", o.crossingsEveryTick,
                 "count the flag's crossings (summary.json, the panel) after every tick, not only after each "
                 "frame's last tick (the state the frame shows); scenes with collisions");
    app.add_flag("--overlay", o.overlay,
                 "draw the panel's graphs and stats (frame time per phase, stretch, iterations) into the "
                 "recorded frames; its cost is the profile's 'overlay' phase");
    app.add_option("--solver", solver, "override the flag's solver, e.g. multigrid:cycles=2 (solvers and keys below)");
    app.add_option("--constraints", constraints,
                   "override the flag's constraints, e.g. tether=0.02,stretch_limit=0.1 (\"\" for none; keys below)")
        ->each([&](const std::string&) { setConstraints = true; });
    app.add_option("--aa", o.aa,
                   "anti-aliasing: auto (the default: post on a software rasterizer, msaa on a GPU), post (one "
                   "pass over the frame), msaa, off")
        ->check(CLI::IsMember({"auto", "post", "msaa", "off"}));
    app.add_option("--msaa", o.msaa, "multisampling with N samples per pixel (0: off); without --aa, it selects msaa")
        ->check(CLI::Range(0, 16));
    app.add_option("--width", o.width, "override the render width")->check(CLI::Range(16, 7680));
    app.add_option("--height", o.height, "override the render height")->check(CLI::Range(16, 4320));
    app.add_flag("--no-progress", o.noProgress, "no progress bar");
    app.add_option("--assets", o.assetsDir, "assets folder (default: $FLAGSIM_ASSETS, the installed ones, or the source tree's)")
        ->check(CLI::ExistingDirectory)
        ->capture_default_str();
    app.footer(cloth::solverHelp() + "\nCommands (the live panel's actions; a script's \"events\"):\n" +
               engine::commandHelp());
    CLI11_PARSE(app, argc, argv);

    try {
        engine::SceneConfig config = engine::loadScene(engine::resolveScenePath(scene, o.assetsDir));
        if (!solver.empty()) {
            std::string error;
            if (!cloth::parseSolverConfig(solver, config.flag.solver, &error))
                throw engine::ConfigError("--solver " + solver + ": " + error);
        }
        if (setConstraints) {
            std::string error;
            if (!cloth::parseConstraints(constraints, config.flag.constraints, &error))
                throw engine::ConfigError("--constraints " + constraints + ": " + error);
        }
        return engine::runScene(config, o);
    } catch (const engine::ConfigError& e) {
        std::fprintf(stderr, "flagsim: error: %s\n", e.what());
        return 2;
    }
}
