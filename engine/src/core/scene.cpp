#include "engine/scene.h"

#include <cstdlib>
#include <filesystem>

#include "core/json_fields.h"

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

}  // namespace

static SceneConfig fromJson(const nlohmann::json& root, const std::string& path);

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
    return fromJson(JsonFields::parseFile(path), path);
}

SceneConfig parseScene(const std::string& text, const std::string& path) {
    return fromJson(JsonFields::parseText(text, path), path);
}

static SceneConfig fromJson(const nlohmann::json& root, const std::string& path) {
    const JsonFields top(path, root);
    top.allowOnly({"name", "description", "subsystems", "timing", "script", "vehicle", "pole",
                   "flag", "air", "camera", "render"});
    SceneConfig s;
    s.file = path;
    s.name = top.string("name", std::filesystem::path(path).stem().string());
    s.description = top.string("description", "");

    if (!top.has("subsystems")) throw ConfigError(path + ": subsystems: missing (list what the scene uses)");
    const auto& list = top.at("subsystems");
    if (!list.is_array()) top.fail("subsystems", list, "must be an array of names");
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string field = "subsystems[" + std::to_string(i) + "]";
        if (!list[i].is_string()) top.fail(field, list[i], "must be a string");
        unsigned bit = 0;
        for (const auto& n : kSubsystemNames)
            if (list[i].get<std::string>() == n.name) bit = n.bit;
        if (!bit) top.fail(field, list[i], "unknown subsystem (known: " + describeSubsystems(~0u) + ")");
        s.subsystems |= bit;
    }
    auto needs = [&](unsigned bit, unsigned required, const char* why) {
        if ((s.subsystems & bit) && !(s.subsystems & required))
            top.fail("subsystems", list, std::string(subsystemName(bit)) + " needs " +
                                             subsystemName(required) + " (" + why + ")");
    };
    needs(kAir, kCloth, "air acts on the flag");
    needs(kCollision, kCloth, "collision keeps the flag out of solids");
    needs(kWindow, kRender, "a window shows rendered frames");
    needs(kRecording, kRender, "recording writes rendered frames");

    const JsonFields timing = top.child("timing");
    timing.allowOnly({"fps", "physics_hz", "max_ticks_per_frame", "duration"});
    s.fps = timing.number("fps", s.fps, 1, 1000);
    s.physicsHz = timing.number("physics_hz", s.physicsHz, 1, 100000);
    s.maxTicksPerFrame = timing.integer("max_ticks_per_frame", s.maxTicksPerFrame, 1, 1000);
    s.duration = timing.number("duration", s.duration, 0.001, 86400);

    s.script = relativeTo(path, top.string("script", ""));
    if (!s.script.empty()) requireFile(top, "script", s.script);

    const JsonFields v = top.child("vehicle");
    v.allowOnly({"model", "wheel_model", "mass", "engine_force", "brake_force", "max_steer",
                 "spawn", "heading", "pole_offset", "pole_height", "pole_radius"});
    s.vehicle.model = relativeTo(path, v.string("model", ""));
    requireFile(v, "model", s.vehicle.model);
    s.vehicle.wheelModel = relativeTo(path, v.string("wheel_model", ""));
    requireFile(v, "wheel_model", s.vehicle.wheelModel);
    s.vehicle.mass = v.number("mass", s.vehicle.mass, 1, 1e6);
    s.vehicle.engineForce = v.number("engine_force", s.vehicle.engineForce, 0, 1e6);
    s.vehicle.brakeForce = v.number("brake_force", s.vehicle.brakeForce, 0, 1e6);
    s.vehicle.maxSteer = v.number("max_steer", s.vehicle.maxSteer, 0, 1.5);
    s.vehicle.spawn = v.vec3("spawn", s.vehicle.spawn, -1e4, 1e4);
    s.vehicle.heading = v.number("heading", s.vehicle.heading, -10, 10);
    s.vehicle.poleOffset = v.vec3("pole_offset", s.vehicle.poleOffset, -100, 100);
    s.vehicle.poleHeight = v.number("pole_height", s.vehicle.poleHeight, 0.1, 100);
    s.vehicle.poleRadius = v.number("pole_radius", s.vehicle.poleRadius, 0.001, 1);

    const JsonFields p = top.child("pole");
    p.allowOnly({"base", "height", "radius"});
    s.pole.base = p.vec3("base", s.pole.base, -1e4, 1e4);
    s.pole.height = p.number("height", s.pole.height, 0.1, 100);
    s.pole.radius = p.number("radius", s.pole.radius, 0.001, 1);

    const JsonFields f = top.child("flag");
    f.allowOnly({"resolution", "width", "height", "mass", "stiffness", "solver", "drag",
                 "thickness", "substeps", "implicit_air"});
    if (f.has("resolution")) {
        const auto& r = f.at("resolution");
        if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer())
            f.fail(f.pathOf("resolution"), r, "must be [particles across, particles down]");
        const auto nx = r[0].get<long long>(), ny = r[1].get<long long>();
        if (nx < 2 || ny < 2 || nx > 513 || ny > 513)
            f.fail(f.pathOf("resolution"), r, "each side must be in [2, 513] particles");
        s.flag.nx = static_cast<int>(nx);
        s.flag.ny = static_cast<int>(ny);
    }
    s.flag.width = f.number("width", s.flag.width, 0.01, 100);
    s.flag.height = f.number("height", s.flag.height, 0.01, 100);
    s.flag.mass = f.number("mass", s.flag.mass, 1e-6, 1e4);
    const JsonFields k = f.child("stiffness");
    k.allowOnly({"structural", "shear", "bend"});
    s.flag.stiffness.structural = k.number("structural", s.flag.stiffness.structural, 1e-3, 1e9);
    s.flag.stiffness.shear = k.number("shear", s.flag.stiffness.shear, 1e-3, 1e9);
    s.flag.stiffness.bend = k.number("bend", s.flag.stiffness.bend, 0, 1e9);
    const JsonFields solver = f.child("solver");
    {
        // The keys and their ranges come from the cloth library's solver table, as for --solver.
        std::string error;
        const std::string name = solver.string("name", s.flag.solver.name);
        if (!cloth::defaultSolverConfig(name, s.flag.solver, &error))
            solver.fail(solver.pathOf("name"), solver.at("name"), error);
        for (const auto& [key, value] : solver.object().items()) {
            if (key == "name") continue;
            const std::string text = value.is_boolean() ? (value.get<bool>() ? "on" : "off")
                                     : value.is_string() ? value.get<std::string>()
                                                         : value.dump();
            if (!value.is_primitive() || value.is_null() ||
                !cloth::setSolverParameter(s.flag.solver, key, text, &error))
                solver.fail(solver.pathOf(key.c_str()), value,
                            value.is_primitive() && !value.is_null() ? error : "must be a number, a word or true/false");
        }
        if (const std::string problem = cloth::validate(s.flag.solver); !problem.empty())
            solver.fail(solver.pathOf("name"), solver.has("name") ? solver.at("name") : nlohmann::json(name), problem);
    }
    s.flag.drag = f.number("drag", s.flag.drag, 0, 1e3);
    s.flag.thickness = f.number("thickness", s.flag.thickness, 0, 1);
    s.flag.substeps = f.integer("substeps", s.flag.substeps, 1, 1000);
    s.flag.implicitAir = f.boolean("implicit_air", s.flag.implicitAir);

    const JsonFields a = top.child("air");
    a.allowOnly({"wind", "density", "drag_coefficient", "lift_coefficient", "friction_coefficient"});
    const Vec3d wind = a.vec3("wind", {0, 0, 0}, -500, 500);
    s.air.wind = cloth::Vec3(wind[0], wind[1], wind[2]);
    s.air.density = a.number("density", s.air.density, 0, 100);
    s.air.dragCoefficient = a.number("drag_coefficient", s.air.dragCoefficient, 0, 100);
    s.air.liftCoefficient = a.number("lift_coefficient", s.air.liftCoefficient, 0, 100);
    s.air.frictionCoefficient = a.number("friction_coefficient", s.air.frictionCoefficient, 0, 100);

    const JsonFields c = top.child("camera");
    c.allowOnly({"mode", "distance", "height", "side", "fov", "smoothing", "eye", "target"});
    s.camera.mode = c.oneOf("mode", s.camera.mode, {"chase", "fixed"});
    s.camera.distance = c.number("distance", s.camera.distance, 0.1, 1000);
    s.camera.height = c.number("height", s.camera.height, -1000, 1000);
    s.camera.side = c.number("side", s.camera.side, -1000, 1000);
    s.camera.fov = c.number("fov", s.camera.fov, 5, 170);
    s.camera.smoothing = c.number("smoothing", s.camera.smoothing, 0.001, 1);
    s.camera.eye = c.vec3("eye", s.camera.eye, -1e4, 1e4);
    s.camera.target = c.vec3("target", s.camera.target, -1e4, 1e4);

    const JsonFields r = top.child("render");
    r.allowOnly({"width", "height", "shadow_map_size"});
    s.render.width = r.integer("width", s.render.width, 16, 7680);
    s.render.height = r.integer("height", s.render.height, 16, 4320);
    if (s.render.width % 2 || s.render.height % 2)
        r.fail(r.pathOf("width"), s.render.width, "width and height must be even (video encoding)");
    s.render.shadowMapSize = r.integer("shadow_map_size", s.render.shadowMapSize, 0, 8192);

    if ((s.subsystems & kVehicle) && (s.subsystems & kRender) && s.vehicle.model.empty())
        throw ConfigError(path + ": vehicle.model: missing (a rendered vehicle needs a model)");
    return s;
}

}  // namespace engine
