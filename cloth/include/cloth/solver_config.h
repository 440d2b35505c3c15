#pragma once
// A solver config as text and as a solver (src/solver_config.cpp): the parsers of
// "name[:key=value,...]" and of single keys (from text or a number), validation, describe(), the
// solver made from a config, and the solver table as data and as text. All loops over the
// registry (solver_kind.h).

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cloth/solver.h"

namespace cloth {

// Parses "name[:key=value[,key=value...]]". Returns false and sets *error (naming the key and
// value) on an unknown name, unknown key or bad value.
bool parseSolverConfig(std::string_view spec, SolverConfig& out, std::string* error);
// The defaults of a kind (false and *error for an unknown name).
bool defaultSolverConfig(std::string_view name, SolverConfig& out, std::string* error);
// Sets one key from its text ("2", "1e-3", "on", "float"), with the same rules as the parser;
// on failure `config` is unchanged and *error names the key, the value and the allowed range.
bool setSolverParameter(SolverConfig& config, std::string_view key, std::string_view value, std::string* error);
// The same from a number (a scene's JSON number): an integer key takes whole numbers only; a
// choice key takes no number.
bool setSolverParameter(SolverConfig& config, std::string_view key, double value, std::string* error);
// Checks a config's ranges; returns an empty string when valid, else what is wrong.
std::string validate(const SolverConfig& config);
// "name:key=value,..." with the keys that differ from the kind's defaults (and those the table
// always shows); parseSolverConfig reads it back to the same config.
std::string describe(const SolverConfig& config);
// The solver table as data for a user interface (the demo's panel): the kinds, and each key of a
// config's kind with its row and its value.
struct SolverKeyInfo {
    enum class Type { Integer, Real, Choice };
    std::string name, doc;
    Type type = Type::Integer;
    std::string range;                 // "[0, 100000]", "fast|gather|reference"
    std::vector<std::string> choices;  // Choice: the allowed words
    double value = 0;                  // Choice: the index of the word
};
std::vector<std::string> solverKindNames();
std::vector<SolverKeyInfo> solverKeys(const SolverConfig& config);
// Every kind with its keys: plain text for --help, or a Markdown table for the README.
std::string solverHelp();
std::string solverTableMarkdown();

// Returns null and sets *error for an invalid config.
std::unique_ptr<Solver> makeSolver(const SolverConfig& config, std::string* error = nullptr);

}  // namespace cloth
