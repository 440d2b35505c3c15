#pragma once
// The solver table: every solver kind, its keys and its factory, in one place. A key is a row:
// name, type, range, default (read from the kind's default settings), one line of doc, and how
// to read and write its field. The parser, validation, describe(), the engine's scene parser
// (through setSolverParameter), --help and the README's table are all loops over these rows.
//
// A new solver is one file (src/solvers/<name>.cpp: its class and factory) and one entry, its
// keys, in solverKinds() (solver_table.cpp).

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cloth/solver.h"

namespace cloth {

// A key's row: name, type, range, one line of doc.
struct KeyRow {
    enum class Type { Integer, Real, Choice };
    const char* name = "";
    Type type = Type::Integer;
    double min = 0, max = 0;          // Integer, Real: the allowed range
    bool minOpen = false, maxOpen = false;
    std::vector<std::string> choices;  // Choice: the allowed words, in the order of their values
    const char* doc = "";
    bool alwaysShown = false;          // describe() prints it even at its default

    std::string range() const;  // "[0, 100000]", "fast|gather|reference"
};

// A key of a Target (SolverConfig for a solver's keys, Constraints for the cloth's constraints):
// its row, and how to read and write its field.
template <class Target>
struct Key : KeyRow {
    std::function<double(const Target&)> get;  // Choice: the index of the word
    std::function<void(Target&, double)> set;

    std::string text(const Target& t) const;  // the value as the parser reads it
};

using SolverKey = Key<SolverConfig>;
using ConstraintKey = Key<Constraints>;

// The constraints' keys (tether, stretch_limit, stretch_passes).
const std::vector<ConstraintKey>& constraintKeys();

struct SolverKind {
    const char* name;
    const char* doc;
    std::function<void(SolverConfig&)> defaults;  // sets the settings variant (and kind-specific defaults)
    std::vector<SolverKey> keys;
    std::function<std::string(const SolverConfig&)> check;  // rules across keys; empty string = fine
    std::function<std::unique_ptr<Solver>(const SolverConfig&)> make;
};

const std::vector<SolverKind>& solverKinds();
const SolverKind* findSolverKind(std::string_view name);
// A kind's config at its defaults.
SolverConfig defaultsOf(const SolverKind& kind);

// Sets a config's settings to S's defaults.
template <class S>
void defaultsTo(SolverConfig& c) {
    c.settings = S{};
}

// Row builders. S is the settings struct of the kind, or SolverConfig itself for the keys every
// kind shares.
namespace keys {

// The target whose keys hold fields of S: Constraints for itself, else a solver's SolverConfig.
template <class S>
using TargetOf = std::conditional_t<std::is_same_v<S, Constraints>, Constraints, SolverConfig>;

template <class S, class Target>
S& part(Target& c) {
    if constexpr (std::is_same_v<S, Target>) return c;
    else return c.template get<S>();
}
template <class S, class Target>
const S& part(const Target& c) {
    if constexpr (std::is_same_v<S, Target>) return c;
    else return c.template get<S>();
}

template <class S>
Key<TargetOf<S>> row(const char* name, KeyRow::Type type, const char* doc) {
    Key<TargetOf<S>> k;
    k.name = name, k.type = type, k.doc = doc;
    return k;
}

template <class S>
Key<TargetOf<S>> integer(const char* name, int S::*field, int min, int max, const char* doc) {
    auto k = row<S>(name, KeyRow::Type::Integer, doc);
    k.min = min, k.max = max;
    k.get = [field](const TargetOf<S>& c) { return double(part<S>(c).*field); };
    k.set = [field](TargetOf<S>& c, double v) { part<S>(c).*field = int(v); };
    return k;
}

template <class S>
Key<TargetOf<S>> real(const char* name, double S::*field, double min, double max, bool minOpen, bool maxOpen,
                      const char* doc) {
    auto k = row<S>(name, KeyRow::Type::Real, doc);
    k.min = min, k.max = max, k.minOpen = minOpen, k.maxOpen = maxOpen;
    k.get = [field](const TargetOf<S>& c) { return part<S>(c).*field; };
    k.set = [field](TargetOf<S>& c, double v) { part<S>(c).*field = v; };
    return k;
}

// A field that takes one of a few words; `values[i]` is the field's value for `words[i]`.
template <class S, class V>
Key<TargetOf<S>> choice(const char* name, V S::*field, std::vector<std::pair<std::string, V>> options, const char* doc) {
    auto k = row<S>(name, KeyRow::Type::Choice, doc);
    std::vector<V> values;
    for (auto& [word, value] : options) k.choices.push_back(word), values.push_back(value);
    k.get = [field, values](const TargetOf<S>& c) {
        for (std::size_t i = 0; i < values.size(); ++i)
            if (values[i] == part<S>(c).*field) return double(i);
        return 0.0;
    };
    k.set = [field, values](TargetOf<S>& c, double v) { part<S>(c).*field = values[std::size_t(v)]; };
    return k;
}

// threads= and precision= of the kinds with a parallel float/double path.
template <class S>
std::vector<SolverKey> parallel(const char* what) {
    return {integer<S>("threads", &S::threads, 1, 64, "worker threads (bit-identical results for any count)"),
            choice<S, bool>("precision", &S::singlePrecision, {{"double", false}, {"float", true}}, what)};
}

template <class Target>
Key<Target> shown(Key<Target> k) {
    k.alwaysShown = true;
    return k;
}

// The key every implicit kind takes (eq. 17).
std::vector<SolverKey> common(bool implicit);
// `own` followed by the common keys.
std::vector<SolverKey> with(std::vector<SolverKey> own, bool implicit);
// a followed by b.
std::vector<SolverKey> operator+(std::vector<SolverKey> a, std::vector<SolverKey> b);

}  // namespace keys

// The solvers' factories, one file each in src/solvers/.
std::unique_ptr<Solver> makeKangChoSolver(const SolverConfig& config);
std::unique_ptr<Solver> makeExactSolver(const SolverConfig& config);  // method=multigrid: makeMultigridSolver
std::unique_ptr<Solver> makeMultigridSolver(const SolverConfig& config);
std::unique_ptr<Solver> makeChebyshevSolver(const SolverConfig& config);
std::unique_ptr<Solver> makeDesbrunSolver(const SolverConfig& config);
std::unique_ptr<Solver> makeExplicitSolver(const SolverConfig& config);
std::unique_ptr<Solver> makeNewtonSolver(const SolverConfig& config);
std::unique_ptr<Solver> makeXpbdSolver(const SolverConfig& config);

}  // namespace cloth
