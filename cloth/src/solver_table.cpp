#include "solver_table.h"

#include <charconv>
#include <cmath>
#include <sstream>

namespace cloth {

const std::vector<SolverKind>& solverKinds() {
    static const std::vector<SolverKind> kinds = {kangchoKind(),   exactKind(),   cgKind(),      multigridKind(),
                                                  chebyshevKind(), desbrunKind(), explicitKind()};
    return kinds;
}

const SolverKind* findSolverKind(std::string_view name) {
    for (const SolverKind& k : solverKinds())
        if (name == k.name) return &k;
    return nullptr;
}

namespace keys {

std::vector<SolverKey> common(bool implicit) {
    std::vector<SolverKey> out;
    if (implicit)
        out.push_back(shown(choice<SolverConfig, bool>("compression", &SolverConfig::compressionRule,
                                                       {{"on", true}, {"off", false}},
                                                       "eq. 17: under compression the Jacobian uses l0 := L")));
    out.push_back(real<SolverConfig>("strain_limit", &SolverConfig::strainLimit, 0, 10, false, true,
                                     "anti-stretch pass after the step: max stretch, 0.1 = 10% (0 = off)"));
    out.push_back(integer<SolverConfig>("strain_passes", &SolverConfig::strainLimitPasses, 1, 1000,
                                        "Gauss-Seidel passes of the anti-stretch pass"));
    return out;
}

std::vector<SolverKey> with(std::vector<SolverKey> own, bool implicit) {
    for (SolverKey& k : common(implicit)) own.push_back(std::move(k));
    return own;
}

}  // namespace keys

namespace {

std::string number(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    // The shortest text that reads back to the same double.
    for (int p = 1; p <= 17; ++p) {
        std::ostringstream t;
        t.precision(p);
        t << v;
        if (std::stod(t.str()) == v) return t.str();
    }
    return s.str();
}

bool parseNumber(std::string_view text, double& out) {
    auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && p == text.data() + text.size() && std::isfinite(out);
}

bool fail(std::string* error, const std::string& message) {
    if (error) *error = message;
    return false;
}

// Reads `text` as the key's value (a choice's index); false if it is not one.
bool readValue(const SolverKey& key, std::string_view text, double& value) {
    switch (key.type) {
        case SolverKey::Type::Choice:
            for (std::size_t i = 0; i < key.choices.size(); ++i)
                if (text == key.choices[i]) return value = double(i), true;
            // Switches also take true/false and 1/0.
            if (key.choices.size() == 2 && key.choices[0] == "on") {
                if (text == "true" || text == "1") return value = 0, true;
                if (text == "false" || text == "0") return value = 1, true;
            }
            return false;
        case SolverKey::Type::Integer: {
            int v = 0;
            auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
            if (ec != std::errc() || p != text.data() + text.size()) return false;
            value = v;
            return true;
        }
        case SolverKey::Type::Real: return parseNumber(text, value);
    }
    return false;
}

bool inRange(const SolverKey& key, double v) {
    if (key.type == SolverKey::Type::Choice) return true;
    return (key.minOpen ? v > key.min : v >= key.min) && (key.maxOpen ? v < key.max : v <= key.max);
}

const SolverKey* findKey(const SolverKind& kind, std::string_view name) {
    for (const SolverKey& k : kind.keys)
        if (name == k.name) return &k;
    return nullptr;
}

std::string knownNames() {
    std::string out;
    for (const SolverKind& k : solverKinds()) out += (out.empty() ? "" : ", ") + std::string(k.name);
    return out;
}

}  // namespace

std::string SolverKey::text(const SolverConfig& c) const {
    const double v = get(c);
    if (type == Type::Choice) return choices[std::size_t(v)];
    if (type == Type::Integer) return std::to_string(int(v));
    return number(v);
}

std::string SolverKey::range() const {
    if (type == Type::Choice) {
        std::string out;
        for (const std::string& c : choices) out += (out.empty() ? "" : "|") + c;
        return out;
    }
    auto bound = [this](double v) { return type == Type::Integer ? std::to_string(int(v)) : number(v); };
    return std::string(minOpen ? "(" : "[") + bound(min) + ", " + bound(max) + (maxOpen ? ")" : "]");
}

bool defaultSolverConfig(std::string_view name, SolverConfig& out, std::string* error) {
    const SolverKind* kind = findSolverKind(name);
    if (!kind) return fail(error, "unknown solver '" + std::string(name) + "' (known: " + knownNames() + ")");
    SolverConfig c;
    c.name = kind->name;
    kind->defaults(c);
    out = std::move(c);
    return true;
}

bool setSolverParameter(SolverConfig& config, std::string_view key, std::string_view value, std::string* error) {
    const SolverKind* kind = findSolverKind(config.name);
    if (!kind) return fail(error, "unknown solver '" + config.name + "' (known: " + knownNames() + ")");
    const SolverKey* k = findKey(*kind, key);
    if (!k) {
        std::string known;
        for (const SolverKey& row : kind->keys) known += (known.empty() ? "" : ", ") + std::string(row.name);
        return fail(error, "solver '" + config.name + "' has no parameter '" + std::string(key) + "' (known: " + known + ")");
    }
    double v = 0;
    if (!readValue(*k, value, v) || !inRange(*k, v))
        return fail(error, "solver '" + config.name + "' parameter " + std::string(key) + " has a bad value '" +
                               std::string(value) + "' (allowed: " + k->range() + ")");
    k->set(config, v);
    return true;
}

bool parseSolverConfig(std::string_view spec, SolverConfig& out, std::string* error) {
    const auto colon = spec.find(':');
    SolverConfig c;
    if (!defaultSolverConfig(spec.substr(0, colon), c, error)) return false;
    std::string_view rest = colon == std::string_view::npos ? "" : spec.substr(colon + 1);
    while (!rest.empty()) {
        const auto comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        rest = comma == std::string_view::npos ? "" : rest.substr(comma + 1);
        const auto eq = item.find('=');
        if (eq == std::string_view::npos)
            return fail(error, "solver parameter '" + std::string(item) + "' is not key=value");
        if (!setSolverParameter(c, item.substr(0, eq), item.substr(eq + 1), error)) return false;
    }
    const std::string problem = validate(c);
    if (!problem.empty()) return fail(error, problem);
    out = std::move(c);
    return true;
}

std::string validate(const SolverConfig& c) {
    const SolverKind* kind = findSolverKind(c.name);
    if (!kind) return "unknown solver '" + c.name + "' (known: " + knownNames() + ")";
    SolverConfig defaults;
    kind->defaults(defaults);
    if (c.settings.index() != defaults.settings.index())
        return "solver '" + c.name + "' holds the settings of another kind";
    for (const SolverKey& k : kind->keys)
        if (!inRange(k, k.get(c)))
            return "solver '" + c.name + "' parameter " + k.name + " = " + k.text(c) + " must be in " + k.range();
    return kind->check ? kind->check(c) : std::string();
}

std::string SolverConfig::describe() const {
    const SolverKind* kind = findSolverKind(name);
    if (!kind) return name;
    SolverConfig defaults;
    defaults.name = name;
    kind->defaults(defaults);
    std::string out = name;
    char separator = ':';
    for (const SolverKey& k : kind->keys) {
        if (!k.alwaysShown && k.get(*this) == k.get(defaults)) continue;
        out += separator + std::string(k.name) + "=" + k.text(*this);
        separator = ',';
    }
    return out;
}

std::string solverHelp() {
    std::ostringstream s;
    s << "Solvers: name[:key=value,...]\n";
    for (const SolverKind& kind : solverKinds()) {
        SolverConfig d;
        d.name = kind.name;
        kind.defaults(d);
        s << "\n  " << kind.name << "  " << kind.doc << "\n";
        for (const SolverKey& k : kind.keys)
            s << "    " << k.name << "=" << k.range() << " (default " << k.text(d) << ")  " << k.doc << "\n";
    }
    return s.str();
}

std::string solverTableMarkdown() {
    std::ostringstream s;
    s << "| solver | key | values | default | what it does |\n|---|---|---|---|---|\n";
    for (const SolverKind& kind : solverKinds()) {
        SolverConfig d;
        d.name = kind.name;
        kind.defaults(d);
        s << "| **" << kind.name << "** | | | | " << kind.doc << " |\n";
        for (const SolverKey& k : kind.keys) {
            std::string range = k.range();  // a '|' inside a table cell must be escaped, even in code
            for (std::size_t p = range.find('|'); p != std::string::npos; p = range.find('|', p + 2)) range.insert(p, "\\");
            s << "| | `" << k.name << "` | `" << range << "` | `" << k.text(d) << "` | " << k.doc << " |\n";
        }
    }
    return s.str();
}

std::unique_ptr<Solver> makeSolver(const SolverConfig& config, std::string* error) {
    const std::string problem = validate(config);
    if (!problem.empty()) {
        if (error) *error = problem;
        return nullptr;
    }
    return findSolverKind(config.name)->make(config);
}

}  // namespace cloth
