#pragma once
// The settings of the solver kind `desbrun` (src/solvers/desbrun.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(DesbrunSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct DesbrunSettings {
    static constexpr const char* kKind = "desbrun";
};

}  // namespace cloth
