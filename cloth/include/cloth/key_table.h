#pragma once
// A key table: the rows of a settings object's keys (name, type, range, default, one line of doc)
// and how to read and write each one's field, with the generic work on them: reading a value from
// text, checking its range, printing it back, and a row of --help or of the README's table. The
// solver kinds' keys (solver_kind.h) and the cloth's constraints' keys (constraint_settings.h)
// are such tables.

#include <functional>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

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
    // Reads `text` as this key's value (a choice's index); false if it is not one or out of range.
    bool read(std::string_view text, double& value) const;
    bool inRange(double value) const;
    // The value as the parser reads it back.
    std::string text(double value) const;
};

// A key of a Target (a solver's SolverConfig, or Constraints): its row, and how to read and write
// its field.
template <class Target>
struct Key : KeyRow {
    std::function<double(const Target&)> get;  // Choice: the index of the word
    std::function<void(Target&, double)> set;

    std::string text(const Target& t) const { return KeyRow::text(get(t)); }
};

// The shortest text that reads back to the same double.
std::string shortestText(double v);

// Calls set(key, value) for each "key=value" of a comma-separated list; false at the first item
// that is not key=value (naming it, as a `what`, in *error) or that set refuses.
bool forEachItem(std::string_view list, const char* what, std::string* error,
                 const std::function<bool(std::string_view, std::string_view)>& set);

// Sets *error (when given) and returns false.
bool failWith(std::string* error, const std::string& message);

// One key's line of --help, or its row of the README's Markdown table (a '|' inside a Markdown
// cell must be escaped, even in code).
template <class Target>
void printKey(std::ostringstream& s, const Key<Target>& k, const Target& defaults, bool markdown) {
    std::string range;
    for (const char ch : k.range()) range += markdown && ch == '|' ? std::string("\\|") : std::string(1, ch);
    if (markdown) s << "| | `" << k.name << "` | `" << range << "` | `" << k.text(defaults) << "` | " << k.doc << " |\n";
    else s << "    " << k.name << "=" << range << " (default " << k.text(defaults) << ")  " << k.doc << "\n";
}

// Row builders for the keys of a Target: KeysOf<Target>::integer("iterations", &S::iterations, ...)
// makes a key of field `iterations` of the part S of a Target (S is the Target itself, or, for a
// solver, its kind's settings: Target::get<S>()).
template <class Target>
struct KeysOf {
    template <class S>
    static S& part(Target& t) {
        if constexpr (std::is_same_v<S, Target>) return t;
        else return t.template get<S>();
    }
    template <class S>
    static const S& part(const Target& t) {
        if constexpr (std::is_same_v<S, Target>) return t;
        else return t.template get<S>();
    }

    static Key<Target> row(const char* name, KeyRow::Type type, const char* doc) {
        Key<Target> k;
        k.name = name, k.type = type, k.doc = doc;
        return k;
    }

    template <class S>
    static Key<Target> integer(const char* name, int S::*field, int min, int max, const char* doc) {
        auto k = row(name, KeyRow::Type::Integer, doc);
        k.min = min, k.max = max;
        k.get = [field](const Target& t) { return double(part<S>(t).*field); };
        k.set = [field](Target& t, double v) { part<S>(t).*field = int(v); };
        return k;
    }

    template <class S>
    static Key<Target> real(const char* name, double S::*field, double min, double max, bool minOpen, bool maxOpen,
                            const char* doc) {
        auto k = row(name, KeyRow::Type::Real, doc);
        k.min = min, k.max = max, k.minOpen = minOpen, k.maxOpen = maxOpen;
        k.get = [field](const Target& t) { return part<S>(t).*field; };
        k.set = [field](Target& t, double v) { part<S>(t).*field = v; };
        return k;
    }

    // A field that takes one of a few words; options[i] pairs the i-th word with the field's value.
    template <class S, class V>
    static Key<Target> choice(const char* name, V S::*field, std::vector<std::pair<std::string, V>> options,
                              const char* doc) {
        auto k = row(name, KeyRow::Type::Choice, doc);
        std::vector<V> values;
        for (auto& [word, value] : options) k.choices.push_back(word), values.push_back(value);
        k.get = [field, values](const Target& t) {
            for (std::size_t i = 0; i < values.size(); ++i)
                if (values[i] == part<S>(t).*field) return double(i);
            return 0.0;
        };
        k.set = [field, values](Target& t, double v) { part<S>(t).*field = values[std::size_t(v)]; };
        return k;
    }

    // The key, printed by describe() even at its default.
    static Key<Target> shown(Key<Target> k) {
        k.alwaysShown = true;
        return k;
    }
};

}  // namespace cloth
