#pragma once
// The settings of the solver kind `vbd` (src/solvers/vbd.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(VbdSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct VbdSettings {
    static constexpr const char* kKind = "vbd";
    int iterations = 10;  // passes over the vertex colors per substep
    int substeps = 1;     // steps of h / substeps per step
    int threads = 1;      // each color's vertices split among them (the same bits for any count)
};

}  // namespace cloth
