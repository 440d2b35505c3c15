#include "engine/scene/scene.h"

#include <cstdlib>
#include <filesystem>
#include <functional>

#include "scene/json_fields.h"

namespace engine {

namespace {

const struct {
    unsigned bit;
    const char* name;
} kSubsystemNames[] = {{kVehicle, "vehicle"},     {kCloth, "cloth"},   {kAir, "air"},
                       {kCollision, "collision"}, {kRender, "render"}, {kWindow, "window"},
                       {kRecording, "recording"}, {kProfiling, "profiling"}};

std::string relativeTo(const std::string& sceneFile, const std::string& path) {
    if (path.empty() || std::filesystem::path(path).is_absolute()) return path;
    return (std::filesystem::path(sceneFile).parent_path() / path).lexically_normal().string();
}

void requireFile(const JsonFields& f, const char* key, const std::string& resolved) {
    std::error_code ec;  // the non-throwing overload: a hostile path (too long, ...) is an error, not a crash
    if (!resolved.empty() && !std::filesystem::is_regular_file(resolved, ec))
        f.fail(f.pathOf(key), f.at(key),
               "file not found (looked for " + resolved + (ec ? ": " + ec.message() : "") + ")");
}

// The scene's subsystems: a list of known names, as a bit mask.
unsigned readSubsystems(const JsonFields& top, const std::string& path) {
    if (!top.has("subsystems")) throw ConfigError(path + ": subsystems: missing (list what the scene uses)");
    const auto& list = top.at("subsystems");
    if (!list.is_array()) top.fail("subsystems", list, "must be an array of names");
    unsigned subsystems = 0;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string field = "subsystems[" + std::to_string(i) + "]";
        if (!list[i].is_string()) top.fail(field, list[i], "must be a string");
        unsigned bit = 0;
        for (const auto& n : kSubsystemNames)
            if (list[i].get<std::string>() == n.name) bit = n.bit;
        if (!bit) top.fail(field, list[i], "unknown subsystem (known: " + describeSubsystems(~0u) + ")");
        subsystems |= bit;
    }
    return subsystems;
}

// Rejects a subsystem listed without one it works on.
void checkSubsystemNeeds(const JsonFields& top, unsigned subsystems) {
    const auto& list = top.at("subsystems");
    auto needs = [&](unsigned bit, unsigned required, const char* why) {
        if ((subsystems & bit) && !(subsystems & required))
            top.fail("subsystems", list, std::string(subsystemName(bit)) + " needs " +
                                             subsystemName(required) + " (" + why + ")");
    };
    needs(kAir, kCloth, "air acts on the flag");
    needs(kCollision, kCloth, "collision keeps the flag out of solids");
    needs(kWindow, kRender, "a window shows rendered frames");
    needs(kRecording, kRender, "recording writes rendered frames");
}

// "timing": frame rate, physics rate, catch-up clamp and duration.
void readTiming(const JsonFields& top, SceneConfig& s) {
    const JsonFields timing = top.child("timing");
    timing.allowOnly({"fps", "physics_hz", "max_ticks_per_frame", "duration"});
    s.fps = timing.number("fps", s.fps, 1, 1000);
    s.physicsHz = timing.number("physics_hz", s.physicsHz, 1, 100000);
    s.maxTicksPerFrame = timing.integer("max_ticks_per_frame", s.maxTicksPerFrame, 1, 1000);
    s.duration = timing.number("duration", s.duration, 0.001, 86400);
}

// "vehicle.model_transform": the model's up axis, yaw (degrees), scale and offset on the chassis.
void readModelTransform(const JsonFields& t, ModelPlacement& placement) {
    t.allowOnly({"up", "yaw", "scale", "offset"});
    placement.up = t.oneOf("up", std::string(1, placement.up), {"y", "z"})[0];
    placement.yawDegrees = t.number("yaw", placement.yawDegrees, -360, 360);
    placement.scale = t.number("scale", placement.scale, 1e-3, 1e3);
    placement.offset = t.vec3("offset", placement.offset, -100, 100);
}

// "vehicle": its model files (relative to the scene file), driving and its pole.
void readVehicle(const JsonFields& top, const std::string& path, SceneConfig::Vehicle& vehicle) {
    const JsonFields v = top.child("vehicle");
    v.allowOnly({"model", "model_transform", "wheel_model", "mass", "engine_force", "brake_force", "max_steer",
                 "spawn", "heading", "pole_offset", "pole_height", "pole_radius"});
    vehicle.model = relativeTo(path, v.string("model", ""));
    requireFile(v, "model", vehicle.model);
    readModelTransform(v.child("model_transform"), vehicle.modelTransform);
    vehicle.wheelModel = relativeTo(path, v.string("wheel_model", ""));
    requireFile(v, "wheel_model", vehicle.wheelModel);
    vehicle.mass = v.number("mass", vehicle.mass, 1, 1e6);
    vehicle.engineForce = v.number("engine_force", vehicle.engineForce, 0, 1e6);
    vehicle.brakeForce = v.number("brake_force", vehicle.brakeForce, 0, 1e6);
    vehicle.maxSteer = v.number("max_steer", vehicle.maxSteer, 0, 1.5);
    vehicle.spawn = v.vec3("spawn", vehicle.spawn, -1e4, 1e4);
    vehicle.heading = v.number("heading", vehicle.heading, -10, 10);
    vehicle.poleOffset = v.vec3("pole_offset", vehicle.poleOffset, -100, 100);
    vehicle.poleHeight = v.number("pole_height", vehicle.poleHeight, 0.1, 100);
    vehicle.poleRadius = v.number("pole_radius", vehicle.poleRadius, 0.001, 1);
}

// "pole": the fixed pole of a scene without a vehicle.
void readPole(const JsonFields& top, SceneConfig::Pole& pole) {
    const JsonFields p = top.child("pole");
    p.allowOnly({"base", "height", "radius"});
    pole.base = p.vec3("base", pole.base, -1e4, 1e4);
    pole.height = p.number("height", pole.height, 0.1, 100);
    pole.radius = p.number("radius", pole.radius, 0.001, 1);
}

// "flag.resolution": [particles across, particles down], each in [2, 513].
void readResolution(const JsonFields& f, SceneConfig::Flag& flag) {
    const auto& r = f.at("resolution");
    if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer())
        f.fail(f.pathOf("resolution"), r, "must be [particles across, particles down]");
    const auto nx = r[0].get<long long>(), ny = r[1].get<long long>();
    if (nx < 2 || ny < 2 || nx > 513 || ny > 513)
        f.fail(f.pathOf("resolution"), r, "each side must be in [2, 513] particles");
    flag.nx = static_cast<int>(nx);
    flag.ny = static_cast<int>(ny);
}

// Each key of `obj` but "name" through a setter: a JSON number stays a number (number(key, value,
// error)); a word, or true/false as on/off, goes as text (text(key, word, error)).
using SetNumber = std::function<bool(const std::string&, double, std::string*)>;
using SetText = std::function<bool(const std::string&, const std::string&, std::string*)>;
void readKeys(const JsonFields& obj, const SetNumber& number, const SetText& text) {
    std::string error;
    for (const auto& [key, value] : obj.object().items()) {
        if (key == "name") continue;
        bool ok = false;
        if (value.is_number()) ok = number(key, value.get<double>(), &error);
        else if (value.is_boolean()) ok = text(key, value.get<bool>() ? "on" : "off", &error);
        else if (value.is_string()) ok = text(key, value.get<std::string>(), &error);
        else error = "must be a number, a word or true/false";
        if (!ok) obj.fail(obj.pathOf(key.c_str()), value, error);
    }
}

// "flag.solver": a solver's name and its settings, checked against the cloth library's solver
// table (as --solver is).
void readSolver(const JsonFields& solver, cloth::SolverConfig& config) {
    std::string error;
    const std::string name = solver.string("name", config.name);
    if (!cloth::defaultSolverConfig(name, config, &error))
        solver.fail(solver.pathOf("name"), solver.at("name"), error);
    readKeys(
        solver,
        [&](const std::string& key, double v, std::string* why) { return cloth::setSolverParameter(config, key, v, why); },
        [&](const std::string& key, const std::string& t, std::string* why) {
            return cloth::setSolverParameter(config, key, t, why);
        });
    if (const std::string problem = cloth::validate(config); !problem.empty())
        solver.fail(solver.pathOf("name"), solver.has("name") ? solver.at("name") : nlohmann::json(name), problem);
}

// "flag.contact": whether the flag's edges are kept out of the pole, the body and the flag itself.
void readContact(const JsonFields& c, cloth::ContactSettings& contact) {
    c.allowOnly({"enabled", "self", "thickness", "max_move", "substep_stride", "self_bounds", "stride_move"});
    contact.enabled = c.boolean("enabled", contact.enabled);
    contact.self = c.boolean("self", contact.self);
    contact.thickness = c.number("thickness", contact.thickness, 1e-4, 0.1);
    contact.maxMove = c.number("max_move", contact.maxMove, 1e-4, 0.1);
    contact.substepStride = c.integer("substep_stride", contact.substepStride, 0, 1000);
    using Bounds = cloth::ContactSettings::SelfBounds;
    const bool halfSpaces = contact.selfBounds == Bounds::HalfSpaces;
    contact.selfBounds = c.oneOf("self_bounds", halfSpaces ? "half_spaces" : "lengths", {"lengths", "half_spaces"}) == "half_spaces"
                             ? Bounds::HalfSpaces
                             : Bounds::Lengths;
    contact.strideMove = c.number("stride_move", contact.strideMove, 0, 1);
}

// "flag": its grid, size, mass, stiffness, solver, drag, collision margin and substeps.
void readFlag(const JsonFields& top, SceneConfig::Flag& flag) {
    const JsonFields f = top.child("flag");
    f.allowOnly({"resolution", "width", "height", "mass", "stiffness", "solver", "constraints", "drag",
                 "thickness", "substeps", "implicit_air", "contact"});
    if (f.has("resolution")) readResolution(f, flag);
    flag.width = f.number("width", flag.width, 0.01, 100);
    flag.height = f.number("height", flag.height, 0.01, 100);
    flag.mass = f.number("mass", flag.mass, 1e-6, 1e4);
    const JsonFields k = f.child("stiffness");
    k.allowOnly({"structural", "shear", "bend"});
    flag.stiffness.structural = k.number("structural", flag.stiffness.structural, 1e-3, 1e9);
    flag.stiffness.shear = k.number("shear", flag.stiffness.shear, 1e-3, 1e9);
    flag.stiffness.bend = k.number("bend", flag.stiffness.bend, 0, 1e9);
    readSolver(f.child("solver"), flag.solver);
    readKeys(
        f.child("constraints"),
        [&](const std::string& key, double v, std::string* why) { return cloth::setConstraint(flag.constraints, key, v, why); },
        [&](const std::string& key, const std::string& t, std::string* why) {
            return cloth::setConstraint(flag.constraints, key, t, why);
        });
    flag.drag = f.number("drag", flag.drag, 0, 1e3);
    flag.thickness = f.number("thickness", flag.thickness, 0, 1);
    flag.substeps = f.integer("substeps", flag.substeps, 1, 1000);
    flag.implicitAir = f.boolean("implicit_air", flag.implicitAir);
    readContact(f.child("contact"), flag.contact);
}

// "air": the wind and the air's density and coefficients.
void readAir(const JsonFields& top, cloth::AirParams& air) {
    const JsonFields a = top.child("air");
    a.allowOnly({"wind", "density", "drag_coefficient", "lift_coefficient", "friction_coefficient"});
    const Vec3d wind = a.vec3("wind", {0, 0, 0}, -500, 500);
    air.wind = cloth::Vec3(wind[0], wind[1], wind[2]);
    air.density = a.number("density", air.density, 0, 100);
    air.dragCoefficient = a.number("drag_coefficient", air.dragCoefficient, 0, 100);
    air.liftCoefficient = a.number("lift_coefficient", air.liftCoefficient, 0, 100);
    air.frictionCoefficient = a.number("friction_coefficient", air.frictionCoefficient, 0, 100);
}

// "camera": a chase camera's placement and easing, or a fixed camera's eye and target.
void readCamera(const JsonFields& top, SceneConfig::Camera& camera) {
    const JsonFields c = top.child("camera");
    c.allowOnly({"mode", "distance", "height", "side", "fov", "smoothing", "target_height", "eye", "target"});
    camera.mode = c.oneOf("mode", camera.mode, {"chase", "fixed"});
    camera.distance = c.number("distance", camera.distance, 0.1, 1000);
    camera.height = c.number("height", camera.height, -1000, 1000);
    camera.side = c.number("side", camera.side, -1000, 1000);
    camera.targetHeight = c.number("target_height", camera.targetHeight, -1000, 1000);
    camera.fov = c.number("fov", camera.fov, 5, 170);
    camera.smoothing = c.number("smoothing", camera.smoothing, 0.001, 1);
    camera.eye = c.vec3("eye", camera.eye, -1e4, 1e4);
    camera.target = c.vec3("target", camera.target, -1e4, 1e4);
}

// "render": the frame size (even, for video encoding), the shadow map's size, the anti-aliasing.
void readRender(const JsonFields& top, SceneConfig::Render& render) {
    const JsonFields r = top.child("render");
    r.allowOnly({"width", "height", "shadow_map_size", "aa", "msaa"});
    render.width = r.integer("width", render.width, 16, 7680);
    render.height = r.integer("height", render.height, 16, 4320);
    if (render.width % 2 || render.height % 2)
        r.fail(r.pathOf("width"), render.width, "width and height must be even (video encoding)");
    render.shadowMapSize = r.integer("shadow_map_size", render.shadowMapSize, 0, 8192);
    render.msaa = r.integer("msaa", render.msaa, 0, 16);
    antiAliasingOf(r.oneOf("aa", toString(render.aa), {"auto", "off", "msaa", "post"}), render.aa);
}

}  // namespace

static SceneConfig sceneFromJson(const nlohmann::json& root, const std::string& path);

const char* subsystemName(unsigned bit) {
    for (const auto& s : kSubsystemNames)
        if (s.bit == bit) return s.name;
    return "?";
}

std::string describeSubsystems(unsigned mask) {
    std::string out;
    for (const auto& s : kSubsystemNames)
        if (mask & s.bit) out += std::string(out.empty() ? "" : ", ") + s.name;
    return out.empty() ? "(none)" : out;
}

std::string defaultAssetsDir() {
    if (const char* env = std::getenv("FLAGSIM_ASSETS"); env && *env) return env;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "flagsim" / "assets";
        if (std::filesystem::is_directory(installed / "scenes", ec)) return installed.string();
    }
    return FLAGSIM_ASSETS_DIR;
}

std::string resolveScenePath(const std::string& nameOrPath, const std::string& assetsDir) {
    if (nameOrPath.find('/') != std::string::npos || nameOrPath.ends_with(".json")) return nameOrPath;
    return assetsDir + "/scenes/" + nameOrPath + ".json";
}

SceneConfig loadScene(const std::string& path) {
    return sceneFromJson(JsonFields::parseFile(path), path);
}

SceneConfig parseScene(const std::string& text, const std::string& path) {
    return sceneFromJson(JsonFields::parseText(text, path), path);
}

static SceneConfig sceneFromJson(const nlohmann::json& root, const std::string& path) {
    const JsonFields top(path, root);
    top.allowOnly({"name", "description", "subsystems", "timing", "script", "vehicle", "pole",
                   "flag", "air", "camera", "render"});
    SceneConfig s;
    s.file = path;
    s.name = top.string("name", std::filesystem::path(path).stem().string());
    s.description = top.string("description", "");
    s.subsystems = readSubsystems(top, path);
    checkSubsystemNeeds(top, s.subsystems);
    readTiming(top, s);
    s.script = relativeTo(path, top.string("script", ""));
    if (!s.script.empty()) requireFile(top, "script", s.script);
    readVehicle(top, path, s.vehicle);
    readPole(top, s.pole);
    readFlag(top, s.flag);
    readAir(top, s.air);
    readCamera(top, s.camera);
    readRender(top, s.render);
    if ((s.subsystems & kVehicle) && (s.subsystems & kRender) && s.vehicle.model.empty())
        throw ConfigError(path + ": vehicle.model: missing (a rendered vehicle needs a model)");
    return s;
}

}  // namespace engine
