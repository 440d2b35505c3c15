#pragma once
// The solver registry: every solver kind with its keys and its factory, and what a kind is
// written with. The parser, validation, describe(), the engine's scene parser (through
// setSolverParameter), threadsOf, --help, the README's table and the demo's panel are all loops
// over it (solver.h).
//
// A kind lives in one file: its key table and its factory, returned by a function the file
// defines with FLAGSIM_SOLVER_KIND(name), beside its public settings struct
// (cloth/solvers/KIND_settings.h). The library's kinds are listed by one line each in
// cloth/CMakeLists.txt (cloth_solver_kind(name file)), which generates the list that registers
// them in that order; a program can add its own with registerSolverKind (the study's Bullet
// peer, the tests' damped_explicit), its step ending in commitStep (step_commit.h).

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cloth/solver.h"
#include "cloth/key_table.h"

namespace cloth {

using SolverKey = Key<SolverConfig>;
using SolverKeys = KeysOf<SolverConfig>;  // SolverKeys::integer("iterations", &S::iterations, ...)

struct SolverKind {
    const char* name;
    const char* doc;
    std::function<void(SolverConfig&)> defaults;  // sets the settings (and kind-specific defaults)
    std::vector<SolverKey> keys;
    std::function<std::string(const SolverConfig&)> check;  // rules across keys; empty string = fine
    std::function<std::unique_ptr<Solver>(const SolverConfig&)> make;
};

// The function that returns kind `name`'s entry (its file defines it; the generated list calls it).
#define FLAGSIM_SOLVER_KIND(name) SolverKind solverKind_##name()

const std::vector<SolverKind>& solverKinds();
const SolverKind* findSolverKind(std::string_view name);
// Adds a kind after the library's; false and *error when its name is taken or it has no name.
bool registerSolverKind(SolverKind kind, std::string* error = nullptr);
// A kind's config at its defaults.
SolverConfig defaultsOf(const SolverKind& kind);

// Sets a config's settings to S's defaults.
template <class S>
void defaultsTo(SolverConfig& c) {
    c.settings = S{};
}

// The key every implicit kind takes (eq. 17): compression=on|off.
SolverKey compressionKey();
// `own`, followed by compressionKey() for an implicit kind.
std::vector<SolverKey> withCommon(std::vector<SolverKey> own, bool implicit);

// threads= of a kind's settings S (bit-identical for any count).
template <class S>
SolverKey threadsKey() {
    return SolverKeys::integer("threads", &S::threads, 1, 64, "worker threads (bit-identical results for any count)");
}

// The threads= setting of the config's kind (1 for the kinds without one).
int threadsOf(const SolverConfig& config);

// A solver of class T holding `config` (the kinds' factories).
template <class T>
std::unique_ptr<Solver> createSolver(const SolverConfig& config) {
    std::unique_ptr<Solver> solver(new T());
    solver->config_ = config;
    solver->pool_ = std::make_shared<ThreadPool>(threadsOf(config));
    return solver;
}

}  // namespace cloth
