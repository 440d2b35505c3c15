#pragma once
// The settings of the solver kind `explicit` (src/solvers/explicit.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(ExplicitSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct ExplicitSettings {
    static constexpr const char* kKind = "explicit";
    int substeps = 1;
};

}  // namespace cloth
