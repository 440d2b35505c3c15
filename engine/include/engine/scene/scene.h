#pragma once
// A scene file (JSON) says which subsystems a scene uses and how each is set up. The engine
// constructs only the declared subsystems; the frame loop has only their phases.
//
// Relative paths inside a scene file are relative to the scene file's folder.

#include <array>
#include <string>

#include "engine/scene/anti_aliasing.h"
#include "cloth/air.h"
#include "cloth/contact.h"
#include "cloth/model.h"
#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "engine/assets/model_placement.h"

namespace engine {

enum Subsystem : unsigned {
    kVehicle = 1u << 0,    // Bullet world with the raycast vehicle
    kCloth = 1u << 1,      // the flag
    kAir = 1u << 2,        // aerodynamic forces on the flag
    kCollision = 1u << 3,  // flag against pole, vehicle body, ground
    kRender = 1u << 4,     // OpenGL renderer (headless through OSMesa unless kWindow)
    kWindow = 1u << 5,     // SDL2 window and live input
    kRecording = 1u << 6,  // frames (and video) written to disk
    kProfiling = 1u << 7,  // per-frame phase profile, CSV and summary
};
const char* subsystemName(unsigned bit);
std::string describeSubsystems(unsigned mask);

using Vec3d = std::array<double, 3>;

struct SceneConfig {
    std::string file;  // where it was loaded from
    std::string name;
    std::string description;
    unsigned subsystems = 0;

    double fps = 60;          // render rate
    double physicsHz = 240;   // fixed physics (and cloth) tick
    int maxTicksPerFrame = 8; // catch-up clamp
    double duration = 10;     // default simulated seconds
    std::string script;       // default input script (vehicle scenes)

    struct Vehicle {
        std::string model;        // glTF/OBJ for the body, loaded with assimp
        ModelPlacement modelTransform;  // its up axis, yaw, scale and offset on the chassis
        std::string wheelModel;   // optional
        double mass = 800;        // kg
        double engineForce = 2000;  // N per driven wheel at full throttle
        double brakeForce = 120;  // N m... brake impulse scale per wheel
        double maxSteer = 0.5;    // rad
        Vec3d spawn = {0, 0.8, 0};
        double heading = 0;       // rad about +y
        Vec3d poleOffset = {0, 0.85, -1.6};  // pole base in the chassis frame (on the body)
        double poleHeight = 2.6;
        double poleRadius = 0.03;
    } vehicle;

    struct Pole {  // a fixed pole for scenes without a vehicle
        Vec3d base = {0, 0, 0};
        double height = 3.0;
        double radius = 0.03;
    } pole;

    struct Flag {
        int nx = 33, ny = 33;
        double width = 1.5, height = 1.0;
        double mass = 0.25;          // kg
        cloth::Stiffness stiffness = {1e3, 1e2, 5};  // see docs/study.md: stiffer flags stop drooping under kangcho:1
        cloth::SolverConfig solver;  // kangcho, 1 iteration, eq. 17 on
        cloth::Constraints constraints;  // tethers and the stretch limit after each step (none)
        double drag = 0.05;          // linear drag rate, 1/s
        double thickness = 0.015;    // collision margin, m
        int substeps = 1;            // cloth steps per physics tick
        bool implicitAir = true;     // air's velocity derivative in the implicit solve (air.h)
        cloth::ContactSettings contact;  // edges kept out of the pole, the body and itself (collision subsystem)
    } flag;

    cloth::AirParams air;

    struct Camera {
        std::string mode = "chase";  // chase | fixed
        double distance = 7, height = 3.0, fov = 50;  // chase: behind, above
        double side = 4;                               // chase: to the left, so the flag shows its face
        double targetHeight = 2.0;                     // chase: looks at this height above the chassis
        double smoothing = 0.1;      // chase: fraction of the heading change followed per frame
        Vec3d eye = {4, 3, 6}, target = {0.75, 1.8, 0};  // fixed
    } camera;

    struct Render {
        int width = 1280, height = 720;
        int shadowMapSize = 1024;
        AntiAliasing aa = AntiAliasing::Auto;  // render/anti_aliasing.h
        int msaa = 4;  // samples per pixel of the main pass with aa = msaa
    } render;
};

// Loads and validates a scene file. Throws ConfigError naming the file, field and value.
SceneConfig loadScene(const std::string& path);
// The same from text that came from `path` (relative paths resolve against its folder).
SceneConfig parseScene(const std::string& text, const std::string& path);
// Where the shipped assets are: $FLAGSIM_ASSETS if set; else <exe>/../share/flagsim/assets when
// the running executable is an installed one; else the source tree's assets (build tree runs).
std::string defaultAssetsDir();
// "NAME" -> <assets>/scenes/NAME.json, a path with '/' or ".json" is used as it is.
std::string resolveScenePath(const std::string& nameOrPath, const std::string& assetsDir);

}  // namespace engine
