#pragma once
// The settings of the solver kind `xpbd` (src/solvers/xpbd.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(XpbdSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct XpbdSettings {
    static constexpr const char* kKind = "xpbd";
    int iterations = 1;
    bool chains = false;
};

}  // namespace cloth
