#pragma once
// The settings of the solver kind `chebyshev` (src/solvers/chebyshev.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(ChebyshevSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct ChebyshevSettings {
    static constexpr const char* kKind = "chebyshev";
    int iterations = 1;
    double rho = 0;  // 0 = estimated each step
};

}  // namespace cloth
