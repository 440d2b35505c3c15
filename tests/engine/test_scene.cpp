// Scene files: every shipped scene loads; malformed ones give an error naming file, field, value.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "engine/scene/config_error.h"
#include "engine/scene/scene.h"

using namespace engine;

namespace {

const std::string kScenes = std::string(FLAGSIM_ASSETS_DIR) + "/scenes/";

std::string sceneError(const std::string& text) {
    try {
        parseScene(text, kScenes + "test.json");
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST(Scene, ShippedScenesLoadWithTheirSubsystems) {
    EXPECT_EQ(loadScene(kScenes + "bench_cloth.json").subsystems, unsigned(kCloth | kAir | kProfiling));
    EXPECT_TRUE(loadScene(kScenes + "hanging_flag.json").subsystems & kRender);
    EXPECT_FALSE(loadScene(kScenes + "hanging_flag.json").subsystems & kVehicle);
    EXPECT_FALSE(loadScene(kScenes + "vehicle_only.json").subsystems & kCloth);
    const SceneConfig demo = loadScene(kScenes + "flag_vehicle.json");
    EXPECT_EQ(demo.flag.nx, 33);
    EXPECT_EQ(demo.flag.solver.name, "kangcho");
    EXPECT_EQ(cloth::describe(demo.flag.solver).rfind("kangcho:iterations=1,", 0), 0u);
    // The HD scene is the same scene with a 65x65 flag.
    SceneConfig hd = loadScene(kScenes + "flag_vehicle_hd.json");
    EXPECT_EQ(hd.flag.nx, 65);
    EXPECT_EQ(hd.flag.ny, 65);
    hd.flag.nx = hd.flag.ny = 33;
    hd.name = demo.name;
    hd.description = demo.description;
    EXPECT_EQ(cloth::describe(hd.flag.solver), cloth::describe(demo.flag.solver));
    EXPECT_EQ(hd.subsystems, demo.subsystems);
    // The stiff scene is the same scene with the study's stiffness, on its true motion's integrator
    // with contact after every fourth substep.
    const SceneConfig stiff = loadScene(kScenes + "flag_vehicle_stiff.json");
    EXPECT_EQ(stiff.subsystems, demo.subsystems);
    EXPECT_EQ(stiff.flag.nx, demo.flag.nx);
    EXPECT_EQ(stiff.flag.stiffness.structural, 1e4);
    EXPECT_EQ(stiff.flag.stiffness.shear, 1e4);
    EXPECT_EQ(stiff.flag.stiffness.bend, 1e3);
    // The true motion's integrator made fast, at the demo's rate, its substeps from the bound and
    // paced at 1 cm.
    EXPECT_EQ(cloth::describe(stiff.flag.solver), "small_steps:substeps=0,max_move=0.01");
    EXPECT_EQ(stiff.flag.mass, demo.flag.mass);
    EXPECT_EQ(stiff.physicsHz, 240);
    // Apart from the flag's stiffness, its solver, its air and contact (after every fourth of its
    // substeps, four times the demo flag's, once its fastest particle has moved 2 cm relative to the
    // pole since the last: within every bound on all seven paths, cheaper on each than after every
    // fourth substep alone), the same scene as the demo's.
    EXPECT_TRUE(stiff.flag.contact.enabled && stiff.flag.contact.self);
    EXPECT_EQ(stiff.flag.contact.substepStride, 4);
    EXPECT_EQ(stiff.flag.contact.strideMove, 0.02);
    auto file = [&](const char* name) {
        std::ifstream in(kScenes + name);
        nlohmann::json j = nlohmann::json::parse(in);
        for (const char* key : {"name", "description"}) j.erase(key);
        for (const char* key : {"stiffness", "solver", "constraints", "implicit_air", "contact"}) j["flag"].erase(key);
        return j;
    };
    EXPECT_EQ(file("flag_vehicle_stiff.json"), file("flag_vehicle.json"));
    // The true-motion scene is the demo's flag, constraints and all, on small_steps paced at 1 cm
    // per substep: the demo's scene but for the flag's solver and contact (after every second
    // substep once its fastest particle has moved 1 cm on the pole: within every bound on all
    // seven paths; 2 cm fails at 50 m/s).
    const SceneConfig trueMotion = loadScene(kScenes + "flag_vehicle_true_motion.json");
    EXPECT_EQ(cloth::describe(trueMotion.flag.solver), "small_steps:substeps=0,max_move=0.01");
    EXPECT_EQ(trueMotion.flag.constraints.describe(), demo.flag.constraints.describe());
    nlohmann::json a = nlohmann::json::parse(std::ifstream(kScenes + "flag_vehicle_true_motion.json"));
    nlohmann::json b = nlohmann::json::parse(std::ifstream(kScenes + "flag_vehicle.json"));
    for (nlohmann::json* j : {&a, &b}) {
        for (const char* key : {"name", "description"}) j->erase(key);
        (*j)["flag"].erase("solver"), (*j)["flag"].erase("contact");
    }
    EXPECT_EQ(a, b);
    EXPECT_TRUE(demo.flag.contact.enabled && demo.flag.contact.self);
    EXPECT_TRUE(trueMotion.flag.contact.enabled && trueMotion.flag.contact.self);
    EXPECT_EQ(trueMotion.flag.contact.substepStride, 2);
    EXPECT_EQ(trueMotion.flag.contact.strideMove, 0.01);
    EXPECT_EQ(demo.flag.contact.substepStride, 1);
    // The scene without contact is the demo's scene but for the flag's contact.
    nlohmann::json c = nlohmann::json::parse(std::ifstream(kScenes + "flag_vehicle_no_contact.json"));
    nlohmann::json d = nlohmann::json::parse(std::ifstream(kScenes + "flag_vehicle.json"));
    for (nlohmann::json* j : {&c, &d}) {
        for (const char* key : {"name", "description"}) j->erase(key);
        (*j)["flag"].erase("contact");
    }
    EXPECT_EQ(c, d);
}

TEST(Scene, SolverKeysFollowTheSolverTable) {
    // The scene parser reads the same keys, with the same ranges, as the --solver string: keys the
    // old scene parser lacked (impl, rho) are read, and keys of another solver are refused.
    const std::string base = R"({"subsystems": ["cloth"], "flag": {"solver": )";
    const SceneConfig a = parseScene(base + R"({"name": "kangcho", "impl": "reference", "iterations": 3}}})", "a.json");
    EXPECT_EQ(cloth::describe(a.flag.solver), "kangcho:iterations=3,impl=reference,compression=on");
    const SceneConfig b = parseScene(base + R"({"name": "chebyshev", "rho": 0.5, "compression": false}}})", "b.json");
    EXPECT_EQ(cloth::describe(b.flag.solver), "chebyshev:iterations=1,rho=0.5,compression=off");
    const SceneConfig c = parseScene(base + R"({"name": "multigrid"}}})", "c.json");
    EXPECT_EQ(cloth::describe(c.flag.solver), "multigrid:cycles=0,compression=on");
}

TEST(Scene, MalformedScenesNameFileFieldAndValue) {
    const std::string base = R"("subsystems": ["cloth"])";
    struct Case {
        std::string text, expect;
    } cases[] = {
        {"{" + base + R"(, "flg": {}})", "flg = {}: unknown field"},
        {"{" + base + R"(, "flag": {"mass": 0}})", "flag.mass = 0: must be in"},
        {"{" + base + R"(, "flag": {"mass": -1}})", "flag.mass = -1: must be in"},
        {"{" + base + R"(, "flag": {"mass": "heavy"}})", "flag.mass = \"heavy\": must be a number"},
        {"{" + base + R"(, "flag": {"mass": 1e999}})", "1e999"},
        {"{" + base + R"(, "flag": {"width": 0}})", "flag.width = 0"},
        {"{" + base + R"(, "flag": {"stiffness": {"structural": 0}}})", "flag.stiffness.structural = 0"},
        {"{" + base + R"(, "flag": {"stiffness": {"bend": -5}}})", "flag.stiffness.bend = -5"},
        {"{" + base + R"(, "flag": {"resolution": [0, 33]}})", "flag.resolution = [0,33]"},
        {"{" + base + R"(, "flag": {"resolution": [1, 33]}})", "flag.resolution = [1,33]"},
        {"{" + base + R"(, "flag": {"resolution": [100000, 100000]}})", "flag.resolution = [100000,100000]"},
        {"{" + base + R"(, "flag": {"resolution": 33}})", "flag.resolution = 33"},
        {"{" + base + R"(, "flag": {"solver": {"name": "magic"}}})", "flag.solver.name = \"magic\": unknown solver 'magic'"},
        {"{" + base + R"(, "flag": {"solver": {"name": "exact", "impl": "fast"}}})", "flag.solver.impl = \"fast\": solver 'exact' has no parameter 'impl'"},
        {"{" + base + R"(, "flag": {"solver": {"name": "multigrid", "tolerance": 2}}})", "flag.solver.tolerance = 2: solver 'multigrid' parameter tolerance has a bad value '2' (allowed: (0, 1))"},
        {"{" + base + R"(, "flag": {"solver": {"name": "multigrid", "damping": 0.5}}})", "flag.solver.damping = 0.5: solver 'multigrid' has no parameter 'damping'"},
        {"{" + base + R"(, "flag": {"solver": {"threads": [2]}}})", "flag.solver.threads = [2]: must be a number"},
        {"{" + base + R"(, "flag": {"solver": {"iterations": -1}}})", "flag.solver.iterations = -1"},
        // JSON numbers are numbers: an integer key takes whole numbers only, a choice no number.
        {"{" + base + R"(, "flag": {"solver": {"iterations": 2.5}}})", "flag.solver.iterations = 2.5: solver 'kangcho' parameter iterations has a bad value '2.5'"},
        {"{" + base + R"(, "flag": {"solver": {"impl": 1}}})", "flag.solver.impl = 1: solver 'kangcho' parameter impl has a bad value '1' (allowed: fast|gather|reference)"},
        {"{" + base + R"(, "flag": {"constraints": {"stretch_passes": 1.5}}})", "flag.constraints.stretch_passes = 1.5: constraint stretch_passes has a bad value '1.5'"},
        {"{" + base + R"(, "flag": {"contact": {"self_bounds": "planes"}}})", "flag.contact.self_bounds = \"planes\": must be one of: lengths, half_spaces"},
        {"{" + base + R"(, "flag": {"contact": {"substep_stride": 1.5}}})", "flag.contact.substep_stride = 1.5"},
        {"{" + base + R"(, "flag": {"contact": {"substep_stride": -1}}})", "flag.contact.substep_stride = -1"},
        {"{" + base + R"(, "flag": {"contact": {"stride_move": -0.01}}})", "flag.contact.stride_move = -0.01"},
        {"{" + base + R"(, "timing": {"physics_hz": 0}})", "timing.physics_hz = 0"},
        {"{" + base + R"(, "timing": {"fps": -60}})", "timing.fps = -60"},
        {"{" + base + R"(, "air": {"wind": [1, 2]}})", "air.wind = [1,2]: must be an array of 3"},
        {"{" + base + R"(, "render": {"width": 1281}})", "render.width = 1281: width and height must be even"},
        {R"({"subsystems": ["cloth", "teleport"]})", "subsystems[1] = \"teleport\": unknown subsystem"},
        {R"({"subsystems": ["air"]})", "air needs cloth"},
        {R"({"flag": {}})", "subsystems: missing"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model": "nowhere.obj"}})", "vehicle.model = \"nowhere.obj\": file not found"},
        {R"({"subsystems": ["vehicle", "render"]})", "vehicle.model: missing"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"scale": 0}}})", "vehicle.model_transform.scale = 0: must be in"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"scale": "NaN"}}})", "vehicle.model_transform.scale = \"NaN\": must be a number"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"up": "x"}}})", "vehicle.model_transform.up = \"x\": must be one of: y, z"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"offset": [0, 1]}}})", "vehicle.model_transform.offset = [0,1]: must be an array of 3"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"scale": -2}}})", "vehicle.model_transform.scale = -2: must be in"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"yaw": "NaN"}}})", "vehicle.model_transform.yaw = \"NaN\": must be a number"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"yaw": 400}}})", "vehicle.model_transform.yaw = 400: must be in"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"offset": [0, "NaN", 0]}}})", "vehicle.model_transform.offset[1] = \"NaN\": must be a number"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"offset": [0, 0, 1000]}}})", "vehicle.model_transform.offset[2] = 1000: must be in"},
        {R"({"subsystems": ["vehicle"], "vehicle": {"model_transform": {"size": 2}}})", "vehicle.model_transform.size = 2: unknown field"},
        {"{" + base + R"(, "script": "../scripts/none.json"})", "script = \"../scripts/none.json\": file not found"},
        // Found by the fuzzer: a path longer than the OS allows made std::filesystem throw.
        {"{" + base + R"(, "script": ")" + std::string(5000, 'x') + R"("})", "file not found"},
        {R"([1, 2])", "must be an object"},
        {R"({"subsystems": )", "not valid JSON"},
    };
    for (const Case& c : cases) {
        const std::string e = sceneError(c.text);
        EXPECT_NE(e.find(kScenes + "test.json"), std::string::npos) << e;
        EXPECT_NE(e.find(c.expect), std::string::npos) << "scene: " << c.text << "\ngot: " << e
                                                         << "\nwanted: " << c.expect;
    }
}

TEST(Scene, MissingSceneFileIsNamed) {
    try {
        loadScene("/nonexistent/scene.json");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json: cannot open"), std::string::npos);
    }
}
