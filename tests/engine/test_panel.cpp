// The live panel in a window, driven by synthetic SDL events as a user's mouse and keyboard
// would: it switches the flag's solver from the paper's step to multigrid and back while the
// vehicle drives, a drag outside it orbits the camera, and the recorded input (actions, the
// panel's commands, the orbit) replays to the same frames, bit for bit. Needs a display: ctest
// runs it under xvfb-run; without one it skips.

#include <gtest/gtest.h>

#include <SDL.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>

#include "engine/scene/input_script.h"
#include "engine/runtime.h"
#include "tests/kinds/damped_explicit_kind.h"

using namespace engine;

namespace {

std::uint64_t fnv1a(const std::vector<std::uint8_t>& bytes) {
    std::uint64_t h = 1469598103934665603ull;
    for (std::uint8_t b : bytes) h = (h ^ b) * 1099511628211ull;
    return h;
}

SDL_Event key(Uint32 type, SDL_Scancode code) {
    SDL_Event e{};
    e.type = type;
    e.key.windowID = SDL_GetWindowID(SDL_GL_GetCurrentWindow());
    e.key.state = type == SDL_KEYDOWN ? SDL_PRESSED : SDL_RELEASED;
    e.key.keysym.scancode = code;
    e.key.keysym.sym = SDL_GetKeyFromScancode(code);
    return e;
}

SDL_Event mouse(Uint32 type, int x, int y, int dx = 0) {
    SDL_Event e{};
    e.type = type;
    if (type == SDL_MOUSEMOTION) {
        e.motion.windowID = SDL_GetWindowID(SDL_GL_GetCurrentWindow());
        e.motion.x = x, e.motion.y = y, e.motion.xrel = dx;
    } else {
        e.button.windowID = SDL_GetWindowID(SDL_GL_GetCurrentWindow());
        e.button.button = SDL_BUTTON_LEFT;
        e.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
        e.button.clicks = 1;
        e.button.x = x, e.button.y = y;
    }
    return e;
}

SceneConfig drivingScene() {
    SceneConfig s = loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/flag_vehicle.json");
    s.render.width = 800;
    s.render.height = 600;
    return s;
}

// Runs to the end, calling `drive` before each frame; the hash of every frame's pixels.
std::vector<std::uint64_t> run(Runtime& rt, const std::function<void(Runtime&)>& drive) {
    std::vector<std::uint64_t> hashes;
    for (;;) {
        drive(rt);
        if (!rt.frame()) break;
        hashes.push_back(fnv1a(rt.pixels()));
    }
    return hashes;
}

}  // namespace

TEST(Panel, SwitchesTheSolverWhileDrivingAndTheRecordedInputReplaysToTheSameFrames) {
    if (!std::getenv("DISPLAY")) GTEST_SKIP() << "no DISPLAY (run under xvfb-run)";
    const std::string recorded = (std::filesystem::temp_directory_path() / "flagsim_panel_input.json").string();
    RunOptions o;
    o.window = true;
    o.readback = true;
    o.frames = 150;
    o.recordInput = recorded;
    std::vector<std::string> solvers;  // the flag's solver at each frame's end
    // The user: throttle from frame 2, then a click on multigrid at frame 40 and on the paper's
    // step at frame 90 (move, press, release: one frame each).
    auto user = [&solvers](Runtime& rt) {
        const int f = rt.frameIndex();
        if (f > 0) solvers.push_back(rt.scene().flag.solver.name);
        SDL_Event e{};
        if (f == 2) e = key(SDL_KEYDOWN, SDL_SCANCODE_UP);
        if (f == 120) e = key(SDL_KEYUP, SDL_SCANCODE_UP);
        for (const auto& [at, label] : {std::pair{40, "solver multigrid"}, std::pair{90, "solver kangcho"}}) {
            if (f < at || f > at + 2) continue;
            const auto rect = rt.widgetRect(label);
            ASSERT_TRUE(rect) << "the panel drew no " << label;
            const int x = int(((*rect)[0] + (*rect)[2]) / 2), y = int(((*rect)[1] + (*rect)[3]) / 2);
            e = mouse(f == at ? SDL_MOUSEMOTION : f == at + 1 ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP, x, y);
        }
        // A drag outside the panel (it is 380 pixels wide at the left): the camera orbits. The
        // mouse moves there first, as a real one does, so the panel knows it has left.
        if (f == 99) e = mouse(SDL_MOUSEMOTION, 600, 300);
        if (f == 100) e = mouse(SDL_MOUSEBUTTONDOWN, 600, 300);
        if (f == 101) e = mouse(SDL_MOUSEMOTION, 680, 300, 80);
        if (f == 102) e = mouse(SDL_MOUSEBUTTONUP, 680, 300);
        if (e.type) SDL_PushEvent(&e);
    };
    std::vector<std::uint64_t> live;
    cloth::State liveEnd;
    {
        Runtime rt(drivingScene(), o);
        live = run(rt, user);
        liveEnd = rt.flag()->state();
        // The solver section is the solver table: every kind, and each key of the kind running.
        for (const std::string& kind : cloth::solverKindNames())
            EXPECT_TRUE(rt.widgetRect("solver " + kind)) << "no radio button for " << kind;
        for (const cloth::SolverKeyInfo& key : cloth::solverKeys(rt.scene().flag.solver)) {
            const std::string label = key.choices.empty() ? key.name : key.name + " " + key.choices.front();
            EXPECT_TRUE(rt.widgetRect(label)) << "no widget for kangcho's key " << label;
        }
        ASSERT_EQ(rt.finish(), 0);
    }
    ASSERT_EQ(live.size(), 150u);
    // The clicks took: multigrid from the frame after the release, the paper's step again later.
    EXPECT_EQ(solvers.at(40), "kangcho");
    EXPECT_EQ(solvers.at(50), "multigrid");
    EXPECT_EQ(solvers.at(140), "kangcho");
    const InputScript script = InputScript::load(recorded);
    ASSERT_EQ(script.events().size(), 3u);
    EXPECT_EQ(script.events()[0].command.name, "solver");
    EXPECT_EQ(script.events()[0].command.value.rfind("multigrid", 0), 0u);
    EXPECT_EQ(script.events()[1].command.value.rfind("kangcho", 0), 0u);
    EXPECT_EQ(script.events()[2].command.name, "camera");
    EXPECT_EQ(script.events()[2].command.value.rfind("-24.000,", 0), 0u) << "80 pixels at 0.3 degrees each";
    double throttle = 0;
    for (const auto& k : script.keyframes()) throttle = std::max(throttle, k.actions.throttle);
    EXPECT_EQ(throttle, 1.0) << "the keyboard drove";

    RunOptions replay = o;
    replay.recordInput.clear();
    replay.scriptPath = recorded;
    Runtime rt(drivingScene(), replay);
    const std::vector<std::uint64_t> again = run(rt, [](Runtime&) {});
    ASSERT_EQ(again.size(), live.size());
    for (std::size_t f = 0; f < live.size(); ++f) ASSERT_EQ(again[f], live[f]) << "frame " << f;
    EXPECT_TRUE(rt.flag()->state().x == liveEnd.x);
    EXPECT_EQ(rt.scene().flag.solver.name, "kangcho");
    std::filesystem::remove(recorded);
}

// A solver kind written in one test file and registered (tests/kinds/damped_explicit_kind.cpp)
// appears in the panel, which reads the registry, with its keys; a click runs it.
TEST(Panel, ListsAKindAddedInOneFileAndRunsIt) {
    if (!std::getenv("DISPLAY")) GTEST_SKIP() << "no DISPLAY (run under xvfb-run)";
    cloth::registerDampedExplicit();
    RunOptions o;
    o.window = true;
    o.readback = true;
    o.frames = 12;
    Runtime rt(drivingScene(), o);
    auto click = [](Runtime& r) {
        const int f = r.frameIndex();
        if (f < 4 || f > 6) return;
        const auto rect = r.widgetRect(std::string("solver ") + cloth::kDampedExplicit);
        ASSERT_TRUE(rect) << "the panel drew no radio button for the registered kind";
        const int x = int(((*rect)[0] + (*rect)[2]) / 2), y = int(((*rect)[1] + (*rect)[3]) / 2);
        SDL_Event e = mouse(f == 4 ? SDL_MOUSEMOTION : f == 5 ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP, x, y);
        SDL_PushEvent(&e);
    };
    run(rt, click);
    EXPECT_EQ(cloth::describe(rt.scene().flag.solver), "damped_explicit:damping=0.01");
    EXPECT_TRUE(rt.widgetRect("damping")) << "no field for the kind's key";
    ASSERT_EQ(rt.finish(), 0);
}

// A number typed out of range into a slider (ctrl+click, "-0", Enter: the soak's seed 11 typed it
// into the shear) is refused, told and counted; the recorded input leaves it out, so it loads and
// replays to the same frames (it used to be recorded, and the recording's loader refused it).
TEST(Panel, AValueTypedOutOfRangeIsRefusedAndTheRecordingStillReplays) {
    if (!std::getenv("DISPLAY")) GTEST_SKIP() << "no DISPLAY (run under xvfb-run)";
    const std::string recorded = (std::filesystem::temp_directory_path() / "flagsim_panel_refused.json").string();
    RunOptions o;
    o.window = true;
    o.readback = true;
    o.frames = 40;
    o.recordInput = recorded;
    auto at = [](Runtime& r, const char* label) {
        const auto rect = r.widgetRect(label);
        EXPECT_TRUE(rect) << "the panel drew no " << label;
        return rect ? std::pair{int(((*rect)[0] + (*rect)[2]) / 2), int(((*rect)[1] + (*rect)[3]) / 2)} : std::pair{0, 0};
    };
    auto user = [&](Runtime& r) {
        const int f = r.frameIndex();
        SDL_Event e{};
        if (f >= 4 && f <= 6) {  // open the flag's section
            const auto [x, y] = at(r, "header Flag and air");
            e = mouse(f == 4 ? SDL_MOUSEMOTION : f == 5 ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP, x, y);
        }
        if (f >= 10 && f <= 12) {  // ctrl+click into the shear slider
            const auto [x, y] = at(r, "shear N/m");
            e = mouse(f == 10 ? SDL_MOUSEMOTION : f == 11 ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP, x, y);
        }
        if (f == 9) e = key(SDL_KEYDOWN, SDL_SCANCODE_LCTRL), e.key.keysym.mod = KMOD_LCTRL;
        if (f == 13) e = key(SDL_KEYUP, SDL_SCANCODE_LCTRL);
        if (f == 15) {
            e.type = SDL_TEXTINPUT;
            e.text.windowID = SDL_GetWindowID(SDL_GL_GetCurrentWindow());
            std::strcpy(e.text.text, "-0");
        }
        if (f == 17) e = key(SDL_KEYDOWN, SDL_SCANCODE_RETURN);
        if (f == 18) e = key(SDL_KEYUP, SDL_SCANCODE_RETURN);
        if (e.type) SDL_PushEvent(&e);
    };
    std::vector<std::uint64_t> live;
    {
        Runtime rt(drivingScene(), o);
        live = run(rt, user);
        EXPECT_EQ(rt.refusals(), 1);
        EXPECT_EQ(rt.scene().flag.stiffness.shear, drivingScene().flag.stiffness.shear);
        ASSERT_EQ(rt.finish(), 0);
    }
    const InputScript script = InputScript::load(recorded);  // threw before: events[..].value = "-0"
    for (const auto& event : script.events()) EXPECT_NE(event.command.name, "shear");
    RunOptions replay = o;
    replay.recordInput.clear();
    replay.scriptPath = recorded;
    Runtime rt(drivingScene(), replay);
    const std::vector<std::uint64_t> again = run(rt, [](Runtime&) {});
    ASSERT_EQ(again, live);
    std::filesystem::remove(recorded);
}
