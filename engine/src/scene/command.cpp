#include "engine/scene/command.h"

#include <cmath>
#include <cstdlib>
#include <functional>
#include <sstream>

#include "cloth/solver.h"
#include "cloth/solver_config.h"

namespace engine {

namespace {

// Reads a whole finite number; false on anything else.
bool readNumber(const std::string& text, double& out) {
    if (text.empty()) return false;
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size() && std::isfinite(out);
}

std::string inRange(const std::string& text, double lo, double hi, bool loOpen) {
    double v = 0;
    if (!readNumber(text, v)) return "is not a number";
    if (v < lo || v > hi || (loOpen && v == lo)) {
        std::ostringstream s;
        s << "is out of range " << (loOpen ? "(" : "[") << lo << ", " << hi << "]";
        return s.str();
    }
    return {};
}

// Three numbers "a,b,c", each in its range; `names` says what they are ("x,y,z").
std::string checkTriple(const std::string& text, const double lo[3], const double hi[3], const char* names) {
    std::vector<std::string> parts;
    std::stringstream s(text);
    for (std::string p; std::getline(s, p, ',');) parts.push_back(p);
    if (parts.size() != 3) return std::string("must be three numbers ") + names;
    for (std::size_t i = 0; i < 3; ++i) {
        const std::string why = inRange(parts[i], lo[i], hi[i], false);
        if (!why.empty()) return "component '" + parts[i] + "' " + why;
    }
    return {};
}

std::string checkWind(const std::string& text) {
    const double lo[3] = {-100, -100, -100}, hi[3] = {100, 100, 100};
    return checkTriple(text, lo, hi, "x,y,z");
}

std::string checkCamera(const std::string& text) {
    const double lo[3] = {-180, -80, 0.2}, hi[3] = {180, 80, 5};
    return checkTriple(text, lo, hi, "yaw,pitch,zoom");
}

std::string checkSolver(const std::string& text) {
    cloth::SolverConfig config;
    std::string error;
    return cloth::parseSolverConfig(text, config, &error) ? std::string() : error;
}

struct CommandRow {
    const char* name;
    const char* value;
    const char* doc;
    std::function<std::string(const std::string&)> check;
};

const std::vector<CommandRow>& commandRows() {
    auto number = [](double lo, double hi, bool loOpen) {
        return [=](const std::string& v) { return inRange(v, lo, hi, loOpen); };
    };
    auto word = [](std::vector<std::string> words) {
        return [=](const std::string& v) {
            std::string all;
            for (const std::string& w : words) {
                if (v == w) return std::string();
                all += (all.empty() ? "" : ", ") + w;
            }
            return "must be one of " + all;
        };
    };
    auto none = [](const std::string& v) { return v.empty() ? std::string() : std::string("takes no value"); };
    static const std::vector<CommandRow> rows = {
        {"solver", "a solver spec", "the flag's solver, e.g. multigrid:cycles=2", checkSolver},
        {"stretch", "N/m, > 0", "structural spring stiffness", number(0, 1e9, true)},
        {"shear", "N/m, > 0", "shear spring stiffness", number(0, 1e9, true)},
        {"bend", "N/m, > 0", "bend spring stiffness", number(0, 1e9, true)},
        {"mass", "kg, > 0", "the flag's total mass", number(0, 1e4, true)},
        {"wind", "x,y,z m/s", "the wind, world frame, each component within 100 m/s", checkWind},
        {"air_density", "kg/m^3", "the air's density, in [0, 100]", number(0, 100, false)},
        {"physics_hz", "ticks/s", "the fixed tick of Bullet and the cloth, in [30, 4000]", number(30, 4000, false)},
        {"camera", "yaw,pitch,zoom", "the chase camera's orbit: degrees, degrees, distance factor", checkCamera},
        {"pause", "on|off", "stop or resume the simulation; frames still render", word({"on", "off"})},
        {"step", "", "one tick while paused", none},
        {"reset", "", "the flag back to rest on its pole", none},
    };
    return rows;
}

}  // namespace

std::string checkCommand(const Command& c) {
    std::string known;
    for (const CommandRow& row : commandRows()) {
        if (c.name == row.name) {
            const std::string why = row.check(c.value);
            return why.empty() ? why : "command " + c.name + " value '" + c.value + "' " + why;
        }
        known += (known.empty() ? "" : ", ") + std::string(row.name);
    }
    return "unknown command '" + c.name + "' (known: " + known + ")";
}

std::string commandHelp() {
    std::ostringstream s;
    for (const CommandRow& row : commandRows())
        s << "  " << row.name << std::string(13 - std::string(row.name).size(), ' ') << row.value
          << std::string(15 - std::string(row.value).size(), ' ') << row.doc << "\n";
    return s.str();
}

double commandNumber(const Command& c) { return std::strtod(c.value.c_str(), nullptr); }

std::vector<double> commandVector(const Command& c) {  // wind, camera
    std::vector<double> out;
    std::stringstream s(c.value);
    for (std::string p; std::getline(s, p, ',');) out.push_back(std::strtod(p.c_str(), nullptr));
    return out;
}

}  // namespace engine
