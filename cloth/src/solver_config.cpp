#include "cloth/solver_config.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "cloth/constraint_settings.h"
#include "cloth/solver_kind.h"

namespace cloth {

namespace {

std::string knownNames() {
    std::string out;
    for (const SolverKind& k : solverKinds()) out += (out.empty() ? "" : ", ") + std::string(k.name);
    return out;
}

std::string unknownSolver(std::string_view name) {
    return "unknown solver '" + std::string(name) + "' (known: " + knownNames() + ")";
}

const SolverKey* findKey(const SolverKind& kind, std::string_view name) {
    for (const SolverKey& k : kind.keys)
        if (name == k.name) return &k;
    return nullptr;
}

}  // namespace

bool defaultSolverConfig(std::string_view name, SolverConfig& out, std::string* error) {
    const SolverKind* kind = findSolverKind(name);
    if (!kind) return failWith(error, unknownSolver(name));
    out = defaultsOf(*kind);
    return true;
}

namespace {

// The key `key` of the config's kind, or null with *error naming what is wrong.
const SolverKey* keyOf(const SolverConfig& config, std::string_view key, std::string* error) {
    const SolverKind* kind = findSolverKind(config.name);
    if (!kind) return failWith(error, unknownSolver(config.name)), nullptr;
    if (const SolverKey* k = findKey(*kind, key)) return k;
    std::string known;
    for (const SolverKey& row : kind->keys) known += (known.empty() ? "" : ", ") + std::string(row.name);
    failWith(error, "solver '" + config.name + "' has no parameter '" + std::string(key) + "' (known: " + known + ")");
    return nullptr;
}

bool badValue(const SolverConfig& config, const SolverKey& k, std::string_view value, std::string* error) {
    return failWith(error, "solver '" + config.name + "' parameter " + k.name + " has a bad value '" +
                               std::string(value) + "' (allowed: " + k.range() + ")");
}

}  // namespace

bool setSolverParameter(SolverConfig& config, std::string_view key, std::string_view value, std::string* error) {
    const SolverKey* k = keyOf(config, key, error);
    if (!k) return false;
    double v = 0;
    if (!k->read(value, v)) return badValue(config, *k, value, error);
    k->set(config, v);
    return true;
}

bool setSolverParameter(SolverConfig& config, std::string_view key, double value, std::string* error) {
    const SolverKey* k = keyOf(config, key, error);
    if (!k) return false;
    const bool whole = std::isfinite(value) && std::floor(value) == value;
    if (k->type == KeyRow::Type::Choice || (k->type == KeyRow::Type::Integer && !whole) || !k->inRange(value))
        return badValue(config, *k, shortestText(value), error);
    k->set(config, value);
    return true;
}

bool parseSolverConfig(std::string_view spec, SolverConfig& out, std::string* error) {
    const auto colon = spec.find(':');
    SolverConfig c;
    if (!defaultSolverConfig(spec.substr(0, colon), c, error)) return false;
    const std::string_view rest = colon == std::string_view::npos ? "" : spec.substr(colon + 1);
    if (!forEachItem(rest, "solver parameter", error, [&](std::string_view key, std::string_view value) {
            return setSolverParameter(c, key, value, error);
        }))
        return false;
    const std::string problem = validate(c);
    if (!problem.empty()) return failWith(error, problem);
    out = std::move(c);
    return true;
}

std::string validate(const SolverConfig& c) {
    const SolverKind* kind = findSolverKind(c.name);
    if (!kind) return unknownSolver(c.name);
    if (c.settings.type() != defaultsOf(*kind).settings.type())
        return "solver '" + c.name + "' holds the settings of another kind";
    for (const SolverKey& k : kind->keys)
        if (!k.inRange(k.get(c)))
            return "solver '" + c.name + "' parameter " + k.name + " = " + k.text(c) + " must be in " + k.range();
    return kind->check ? kind->check(c) : std::string();
}

std::string describe(const SolverConfig& config) {
    const SolverKind* kind = findSolverKind(config.name);
    if (!kind) return config.name;
    const SolverConfig defaults = defaultsOf(*kind);
    std::string out = config.name;
    char separator = ':';
    for (const SolverKey& k : kind->keys) {
        if (!k.alwaysShown && k.get(config) == k.get(defaults)) continue;
        out += separator + std::string(k.name) + "=" + k.text(config);
        separator = ',';
    }
    return out;
}

namespace {

// The table as text: plain for --help, or Markdown for the README.
std::string printTable(bool markdown) {
    std::ostringstream s;
    s << (markdown ? "| solver | key | values | default | what it does |\n|---|---|---|---|---|\n"
                   : "Solvers: name[:key=value,...]\n");
    for (const SolverKind& kind : solverKinds()) {
        const SolverConfig d = defaultsOf(kind);
        if (markdown) s << "| **" << kind.name << "** | | | | " << kind.doc << " |\n";
        else s << "\n  " << kind.name << "  " << kind.doc << "\n";
        for (const SolverKey& k : kind.keys) printKey(s, k, d, markdown);
    }
    const char* what = "the cloth's corrections after any solver's step (a scene's flag.constraints, --constraints)";
    if (markdown) s << "| **constraints** | | | | " << what << " |\n";
    else s << "\nConstraints: key=value,...  " << what << "\n";
    for (const ConstraintKey& k : constraintKeys()) printKey(s, k, Constraints{}, markdown);
    return s.str();
}

}  // namespace

std::vector<std::string> solverKindNames() {
    std::vector<std::string> names;
    for (const SolverKind& kind : solverKinds()) names.push_back(kind.name);
    return names;
}

std::vector<SolverKeyInfo> solverKeys(const SolverConfig& config) {
    std::vector<SolverKeyInfo> out;
    const SolverKind* kind = findSolverKind(config.name);
    if (!kind) return out;
    for (const SolverKey& k : kind->keys) {
        SolverKeyInfo info;
        info.name = k.name, info.doc = k.doc;
        info.type = SolverKeyInfo::Type(int(k.type));
        info.range = k.range();
        info.choices = k.choices;
        info.value = k.get(config);
        out.push_back(std::move(info));
    }
    return out;
}

std::string solverHelp() { return printTable(false); }
std::string solverTableMarkdown() { return printTable(true); }

std::unique_ptr<Solver> makeSolver(const SolverConfig& config, std::string* error) {
    const std::string problem = validate(config);
    if (!problem.empty()) {
        if (error) *error = problem;
        return nullptr;
    }
    return findSolverKind(config.name)->make(config);
}

}  // namespace cloth
