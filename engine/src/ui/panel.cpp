// The panel's life: its ImGui context, a frame of it, the graphs' history.

#include "ui/panel.h"

#include <imgui.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <deque>
#include <cstdio>
#include <stdexcept>

#include "engine/render/gl_context.h"
#include "ui/imgui_gl.h"

namespace engine {

// The last seconds of each measured series, oldest first.
struct Panel::History {
    static constexpr std::size_t kFrames = 300;  // 5 s at 60 frames per second
    std::map<std::string, std::deque<float>> series;
    std::vector<std::string> order;  // the phases in the profile's order, then the flag's series
    void add(const std::string& name, double value) {
        auto [it, inserted] = series.try_emplace(name);
        if (inserted) order.push_back(name);
        it->second.push_back(float(value));
        if (it->second.size() > kFrames) it->second.pop_front();
    }
};

Panel::Panel(GLContext& context, bool interactive)
    : interactive_(interactive), history_(std::make_unique<History>()) {
    const char* missing = nullptr;
    if (!ui::loadImguiGl(context.procAddress(), &missing))
        throw std::runtime_error(std::string("the panel needs OpenGL function ") + missing);
    IMGUI_CHECKVERSION();
    ImGuiContext* previous = ImGui::GetCurrentContext();
    ctx_ = ImGui::CreateContext();
    ImGui::SetCurrentContext(ctx_);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the working folder: every run starts the same
    io.LogFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui::GetStyle().Alpha = interactive ? 0.95f : 0.85f;
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
        ImGui::DestroyContext(ctx_);
        ImGui::SetCurrentContext(previous);
        throw std::runtime_error("the panel's OpenGL 3 renderer did not start");
    }
}

Panel::~Panel() {
    ImGui::SetCurrentContext(ctx_);
    ImGui_ImplOpenGL3_Shutdown();
    ImGui::DestroyContext(ctx_);
}

PanelRequests Panel::takeRequests() {
    PanelRequests r = std::move(requests_);
    requests_ = {};
    return r;
}

std::optional<std::array<float, 4>> Panel::widgetRect(const std::string& label) const {
    const auto it = rects_.find(label);
    if (it == rects_.end()) return std::nullopt;
    return it->second;
}

std::vector<std::string> Panel::widgetLabels() const {
    std::vector<std::string> labels;
    for (const auto& [label, rect] : rects_) labels.push_back(label);
    return labels;
}

void Panel::remember(const std::string& label) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    rects_[label] = {a.x, a.y, b.x, b.y};
}

void Panel::draw(const PanelState& s, int width, int height, double frameSeconds) {
    ImGui::SetCurrentContext(ctx_);
    for (std::size_t i = 0; i < s.phases.size() && i < s.phaseMs.size(); ++i) history_->add(s.phases[i], s.phaseMs[i]);
    if (s.hasFlag) {
        history_->add("p99 stretch %", 100 * s.p99Stretch);
        history_->add("max stretch %", 100 * s.maxStretch);
        history_->add("iterations / step", s.iterationsPerStep);
        if (s.crossings >= 0) history_->add("crossings", s.crossings);
    }
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(width), float(height));
    io.DeltaTime = float(std::max(frameSeconds, 1e-4));
    for (int b = 0; b < 3; ++b) {  // a press shorter than a frame is still seen by one frame
        io.MouseDown[b] = mouse_.down[b] || mouse_.pressed[b];
        mouse_.pressed[b] = false;
    }
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(interactive_ ? 380.f : 330.f, 0), ImGuiCond_Always);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                   (interactive_ ? 0 : ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_NoTitleBar);
    ImGui::Begin("flagsim", nullptr, flags);
    rects_.clear();  // the widgets of this frame only
    drawRun(s);
    auto header = [this](const char* title, ImGuiTreeNodeFlags open) {
        const bool shown = ImGui::CollapsingHeader(title, open);
        remember(std::string("header ") + title);
        return shown;
    };
    if (interactive_ && s.hasFlag) {
        if (header("Solver", ImGuiTreeNodeFlags_DefaultOpen)) drawSolver(s);
        if (header("Flag and air", 0)) drawFlag(s);
    }
    if (!interactive_ || header("Profile and stats", ImGuiTreeNodeFlags_DefaultOpen)) drawGraphs(s);
    const std::string& refusal = !error_.empty() ? error_ : s.refusal;
    if (!refusal.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", refusal.c_str());
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    area_ = {at.x, at.y, at.x + size.x, at.y + size.y};
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

namespace {

void plot(const char* id, const std::deque<float>& d, float height) {
    std::vector<float> values(d.begin(), d.end());
    const float top = values.empty() ? 1.f : *std::max_element(values.begin(), values.end());
    ImGui::PlotLines(id, values.data(), int(values.size()), 0, nullptr, 0.f, std::max(top, 1e-3f) * 1.1f,
                     ImVec2(ImGui::GetContentRegionAvail().x, height));
}

struct Summary {
    float now = 0, mean = 0, max = 0;
};
Summary summarize(const std::deque<float>& d) {
    Summary s;
    if (d.empty()) return s;
    s.now = d.back();
    for (float v : d) s.mean += v / float(d.size()), s.max = std::max(s.max, v);
    return s;
}

}  // namespace

// The frame time and the flag's stretch and iterations as plots over the last seconds, then each
// phase's milliseconds (now, mean, max) as a table; Bullet's zones folded away.
void Panel::drawGraphs(const PanelState&) {
    const auto& series = history_->series;
    auto line = [&](const char* name, const char* format) {
        const auto it = series.find(name);
        if (it == series.end()) return;
        const Summary s = summarize(it->second);
        ImGui::Text(format, s.now, s.max);
        plot((std::string("##") + name).c_str(), it->second, 32);
    };
    line("frame", "frame %.2f ms (max %.2f)");
    line("p99 stretch %", "p99 stretch %.2f%% (max %.2f)");
    line("iterations / step", "solver iterations per step %.1f (max %.1f)");
    const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp;
    if (!ImGui::BeginTable("phases", 4, flags)) return;
    ImGui::TableSetupColumn("phase, ms");
    ImGui::TableSetupColumn("now");
    ImGui::TableSetupColumn("mean");
    ImGui::TableSetupColumn("max");
    ImGui::TableHeadersRow();
    for (const std::string& name : history_->order) {
        if (name.rfind("bullet:", 0) == 0 || name.find(' ') != std::string::npos) continue;
        const Summary s = summarize(series.at(name));
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(name.c_str());
        for (float v : {s.now, s.mean, s.max}) {
            ImGui::TableNextColumn();
            ImGui::Text("%.2f", v);
        }
    }
    ImGui::EndTable();
    const auto maxStretch = series.find("max stretch %");
    if (maxStretch != series.end()) ImGui::Text("max stretch %.2f%%", summarize(maxStretch->second).now);
}

}  // namespace engine
