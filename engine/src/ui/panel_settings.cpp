// The panel's settings: the run (scene, pause, step, reset), the solver from the solver table,
// the flag and the air. Every change is a Command or a request; nothing here touches the scene.

#include <imgui.h>

#include <cmath>
#include <cstdio>

#include "ui/panel.h"

namespace engine {

namespace {

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

}  // namespace

bool Panel::editNumber(const std::string& label, double current,
                       const std::function<bool(const char*, double*)>& widget, double* out) {
    double& v = held_[label];
    if (active_ != label) v = current;
    widget(label.c_str(), &v);
    remember(label);
    if (ImGui::IsItemActive()) active_ = label;
    else if (active_ == label) active_.clear();
    if (!ImGui::IsItemDeactivatedAfterEdit()) return false;
    if (!std::isfinite(v)) {
        refuse(label + ": " + number(v) + " is not a finite number");
        return false;
    }
    *out = v;
    return true;
}

// Scene, restart, pause, step, reset, and what is running.
void Panel::drawRun(const PanelState& s) {
    ImGui::Text("%s   t = %.2f s%s", s.scene.c_str(), s.simTime, s.paused ? "   (paused)" : "");
    ImGui::TextDisabled("anti-aliasing: %s", s.antiAliasing.c_str());
    if (s.hasFlag) ImGui::TextWrapped("solver %s", cloth::describe(s.solver).c_str());
    if (!interactive_) return;
    if (s.switchNote.empty()) {
        if (ImGui::BeginCombo("scene", s.scene.c_str())) {
            for (const std::string& name : s.scenes)
                if (ImGui::Selectable(name.c_str(), name == s.scene)) requests_.scene = name;
            ImGui::EndCombo();
        }
        remember("scene");
        if (ImGui::Button("restart")) requests_.restart = true;
        remember("restart");
        ImGui::SameLine();
    } else {
        ImGui::TextDisabled("%s", s.switchNote.c_str());
    }
    if (ImGui::Button(s.paused ? "resume" : "pause")) emit({"pause", s.paused ? "off" : "on"});
    remember("pause");
    ImGui::SameLine();
    ImGui::BeginDisabled(!s.paused);
    if (ImGui::Button("step")) emit({"step", ""});
    ImGui::EndDisabled();
    remember("step");
    if (s.hasFlag) {
        ImGui::SameLine();
        if (ImGui::Button("reset flag")) emit({"reset", ""});
        remember("reset flag");
    }
}

void Panel::emitSolver(const cloth::SolverConfig& config) {
    emit({"solver", cloth::describe(config)});
    error_.clear();
}

// The solver kinds as radio buttons, then the current kind's keys, all from the solver table.
void Panel::drawSolver(const PanelState& s) {
    int column = 0;
    for (const std::string& kind : cloth::solverKindNames()) {
        if (column++ % 4) ImGui::SameLine();
        if (ImGui::RadioButton(kind.c_str(), kind == s.solver.name) && kind != s.solver.name) {
            cloth::SolverConfig config;
            std::string error;
            if (cloth::defaultSolverConfig(kind, config, &error)) {
                config.compressionRule = s.solver.compressionRule;
                emitSolver(config);
            } else {
                refuse(error);
            }
        }
        remember("solver " + kind);
    }
    for (const cloth::SolverKeyInfo& key : cloth::solverKeys(s.solver)) drawSolverKey(s, key);
}

// One key: its words as radio buttons, or its number in a field; its doc as the tooltip.
void Panel::drawSolverKey(const PanelState& s, const cloth::SolverKeyInfo& key) {
    std::string text;
    if (key.type == cloth::SolverKeyInfo::Type::Choice) {
        ImGui::TextUnformatted(key.name.c_str());
        for (std::size_t i = 0; i < key.choices.size(); ++i) {
            ImGui::SameLine();
            const std::string label = key.choices[i] + "##" + key.name;
            if (ImGui::RadioButton(label.c_str(), std::size_t(key.value) == i) && std::size_t(key.value) != i)
                text = key.choices[i];
            remember(key.name + " " + key.choices[i]);
        }
    } else {
        const bool integer = key.type == cloth::SolverKeyInfo::Type::Integer;
        double v = 0;
        auto field = [integer](const char* label, double* value) {
            return ImGui::InputDouble(label, value, integer ? 1.0 : 0.0, 0.0, integer ? "%.0f" : "%g");
        };
        if (editNumber(key.name, key.value, field, &v)) text = number(integer ? std::round(v) : v);
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s (%s)", key.doc.c_str(), key.range.c_str());
    if (text.empty()) return;
    cloth::SolverConfig config = s.solver;
    std::string error;
    if (cloth::setSolverParameter(config, key.name, text, &error)) emitSolver(config);
    else refuse(error);
}

// Stiffness, mass, wind, air density and the physics rate, each applied when its edit ends.
void Panel::drawFlag(const PanelState& s) {
    double v = 0;
    auto log = [](float lo, float hi, const char* format) {
        return [=](const char* label, double* value) {
            float f = float(*value);
            const bool changed = ImGui::SliderFloat(label, &f, lo, hi, format, ImGuiSliderFlags_Logarithmic);
            *value = f;
            return changed;
        };
    };
    if (editNumber("stretch N/m", s.stiffness.structural, log(10, 1e5f, "%.0f"), &v)) emit({"stretch", number(v)});
    if (editNumber("shear N/m", s.stiffness.shear, log(1, 1e5f, "%.0f"), &v)) emit({"shear", number(v)});
    if (editNumber("bend N/m", s.stiffness.bend, log(0.1f, 1e4f, "%.1f"), &v)) emit({"bend", number(v)});
    if (editNumber("mass kg", s.mass, log(0.01f, 10, "%.3f"), &v)) emit({"mass", number(v)});
    if (s.hasAir) {
        const char* axes[3] = {"wind x m/s", "wind y m/s", "wind z m/s"};
        for (int a = 0; a < 3; ++a) {
            auto slider = [](const char* label, double* value) {
                float f = float(*value);
                const bool changed = ImGui::SliderFloat(label, &f, -40, 40, "%.1f");
                *value = f;
                return changed;
            };
            if (editNumber(axes[a], s.wind[a], slider, &v)) {
                Eigen::Vector3d w = s.wind;
                w[a] = v;
                emit({"wind", number(w.x()) + "," + number(w.y()) + "," + number(w.z())});
            }
        }
        if (editNumber("air density", s.airDensity, log(0.01f, 20, "%.2f"), &v)) emit({"air_density", number(v)});
    }
    ImGui::TextUnformatted("physics Hz");
    for (int hz : {60, 120, 240, 480}) {
        ImGui::SameLine();
        const std::string label = std::to_string(hz);
        if (ImGui::RadioButton(label.c_str(), std::lround(s.physicsHz) == hz) && std::lround(s.physicsHz) != hz)
            emit({"physics_hz", label});
        remember("physics_hz " + label);
    }
}

}  // namespace engine
