#include "cloth/solver_kind.h"

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

int threadsOf(const SolverConfig& config) {
    const SolverKind* kind = findSolverKind(config.name);
    const SolverKey* threads = nullptr;
    if (kind)
        for (const SolverKey& key : kind->keys)
            if (std::string_view(key.name) == "threads") threads = &key;
    return threads ? int(threads->get(config)) : 1;
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

}  // namespace cloth
