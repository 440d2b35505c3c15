#pragma once
// The settings of the solver kind `small_steps` (src/solvers/small_steps.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(SmallStepsSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct SmallStepsSettings {
    static constexpr const char* kKind = "small_steps";
    int substeps = 0;
    double fraction = 1.0;
    double maxMove = 0;  // m; 0 = the substeps from the stability bound alone
    int threads = 1;
    int parallelFrom = 2048;  // particles: a smaller cloth steps on one thread whatever `threads`
};

}  // namespace cloth
