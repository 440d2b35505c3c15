#pragma once
// The live panel, drawn with Dear ImGui over the scene: the scene and the flag's settings as
// widgets, and live graphs (the frame's phases over the last seconds, the flag's stretch, the
// solver's iterations), as the field's sample browsers show them. A widget never changes the
// scene itself: it makes a Command (engine/scene/command.h), which the runtime applies at the next
// frame's start and records, so a live session replays to identical frames. Switching scene or
// restarting is a request to the runner (a new run), not a command.
//
// The solver's section is generated from the solver table (cloth::solverKeys), so the panel,
// --help and the README list the same kinds and keys.

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "ui/panel_types.h"

struct ImGuiContext;

namespace engine {

class GLContext;

class Panel {
public:
    // On the current GL context of `context`. `interactive`: widgets take input (a window);
    // otherwise the panel is drawn as an overlay of the recorded frames. Throws
    // std::runtime_error when a GL function the panel draws with is missing.
    Panel(GLContext& context, bool interactive);
    ~Panel();
    Panel(const Panel&) = delete;
    Panel& operator=(const Panel&) = delete;

    // An SDL_Event (window builds); true when the panel takes it (the mouse is over it, or a text
    // field has the keyboard), so it must not drive the vehicle.
    bool handleEvent(const void* sdlEvent);
    // Adds the frame to the graphs' history and draws the panel into the current framebuffer.
    void draw(const PanelState& state, int width, int height, double frameSeconds);
    PanelRequests takeRequests();
    // The screen rectangle (x0, y0, x1, y1, in pixels from the top left) where the widget with
    // this label was last drawn; tests click there with synthetic events.
    std::optional<std::array<float, 4>> widgetRect(const std::string& label) const;
    // The labels of the widgets drawn in the last frame (widgetRect finds each).
    std::vector<std::string> widgetLabels() const;
    // The panel's own rectangle when it was last drawn (the same units).
    const std::array<float, 4>& area() const { return area_; }

private:
    std::array<float, 4> area_{};
    struct History;
    void drawRun(const PanelState& s);
    void drawSolver(const PanelState& s);
    void drawSolverKey(const PanelState& s, const cloth::SolverKeyInfo& key);
    void drawFlag(const PanelState& s);
    void drawGraphs(const PanelState& s);
    void emit(Command c) { requests_.commands.push_back(std::move(c)); }
    // Shows why the panel does not ask for what was entered, and tells the runtime (stderr).
    void refuse(const std::string& why) {
        error_ = why;
        requests_.refusals.push_back(why);
    }
    void emitSolver(const cloth::SolverConfig& config);
    void remember(const std::string& label);
    // A number in a widget: shown from the scene while not held, kept while the user edits it;
    // true once an edit is finished, with the value in *out.
    bool editNumber(const std::string& label, double current, const std::function<bool(const char*, double*)>& widget,
                    double* out);

    ImGuiContext* ctx_ = nullptr;
    bool interactive_;
    std::unique_ptr<History> history_;
    PanelRequests requests_;
    std::string error_;                                  // the last refused edit
    std::map<std::string, double> held_;                 // numbers being edited, by label
    std::string active_;                                 // the label of the widget being edited
    std::map<std::string, std::array<float, 4>> rects_;  // label -> last drawn rectangle
    struct Held {  // mouse buttons held, and a press not yet seen by a frame
        bool down[3] = {false, false, false}, pressed[3] = {false, false, false};
    } mouse_;
};

}  // namespace engine
