#include "registry/solver_registry.h"

#include <algorithm>
#include <sstream>

#include "registry/constraint_keys.h"

namespace cloth {

// The library's kinds, one line each in cloth/CMakeLists.txt: FLAGSIM_LIST_KIND(name), in order.
#define FLAGSIM_LIST_KIND(name) SolverKind solverKind_##name();
#include "solver_kinds.inc"
#undef FLAGSIM_LIST_KIND

namespace {

std::vector<SolverKind>& registry() {
    static std::vector<SolverKind> kinds = [] {
        std::vector<SolverKind> k;
#define FLAGSIM_LIST_KIND(name) k.push_back(solverKind_##name());
#include "solver_kinds.inc"
#undef FLAGSIM_LIST_KIND
        return k;
    }();
    return kinds;
}

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

const std::vector<SolverKind>& solverKinds() { return registry(); }

const SolverKind* findSolverKind(std::string_view name) {
    for (const SolverKind& k : solverKinds())
        if (name == k.name) return &k;
    return nullptr;
}

bool registerSolverKind(SolverKind kind, std::string* error) {
    if (!kind.name || !*kind.name || !kind.defaults || !kind.make)
        return failWith(error, "a solver kind needs a name, its defaults and a factory");
    if (findSolverKind(kind.name)) return failWith(error, "solver kind '" + std::string(kind.name) + "' exists already");
    registry().push_back(std::move(kind));
    return true;
}

SolverConfig::SolverConfig() {
    if (const SolverKind* paper = findSolverKind("kangcho")) paper->defaults(*this);
}

SolverConfig defaultsOf(const SolverKind& kind) {
    SolverConfig c;
    c.name = kind.name;
    kind.defaults(c);
    return c;
}

SolverKey compressionKey() {
    return SolverKeys::shown(SolverKeys::choice("compression", &SolverConfig::compressionRule,
                                                {{"on", true}, {"off", false}},
                                                "eq. 17: under compression the Jacobian uses l0 := L"));
}

std::vector<SolverKey> withCommon(std::vector<SolverKey> own, bool implicit) {
    if (implicit) own.push_back(compressionKey());
    return own;
}

bool defaultSolverConfig(std::string_view name, SolverConfig& out, std::string* error) {
    const SolverKind* kind = findSolverKind(name);
    if (!kind) return failWith(error, unknownSolver(name));
    out = defaultsOf(*kind);
    return true;
}

bool setSolverParameter(SolverConfig& config, std::string_view key, std::string_view value, std::string* error) {
    const SolverKind* kind = findSolverKind(config.name);
    if (!kind) return failWith(error, unknownSolver(config.name));
    const SolverKey* k = findKey(*kind, key);
    if (!k) {
        std::string known;
        for (const SolverKey& row : kind->keys) known += (known.empty() ? "" : ", ") + std::string(row.name);
        return failWith(error, "solver '" + config.name + "' has no parameter '" + std::string(key) + "' (known: " +
                                   known + ")");
    }
    double v = 0;
    if (!k->read(value, v))
        return failWith(error, "solver '" + config.name + "' parameter " + std::string(key) + " has a bad value '" +
                                   std::string(value) + "' (allowed: " + k->range() + ")");
    k->set(config, v);
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

std::string SolverConfig::describe() const {
    const SolverKind* kind = findSolverKind(name);
    if (!kind) return name;
    const SolverConfig defaults = defaultsOf(*kind);
    std::string out = name;
    char separator = ':';
    for (const SolverKey& k : kind->keys) {
        if (!k.alwaysShown && k.get(*this) == k.get(defaults)) continue;
        out += separator + std::string(k.name) + "=" + k.text(*this);
        separator = ',';
    }
    return out;
}

int threadsOf(const SolverConfig& config) {
    const SolverKind* kind = findSolverKind(config.name);
    const SolverKey* threads = kind ? findKey(*kind, "threads") : nullptr;
    return threads ? int(threads->get(config)) : 1;
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
