#pragma once
// The settings of the solver kind `exact` (src/solvers/exact.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(ExactSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct ExactSettings {
    static constexpr const char* kKind = "exact";
    enum class Method { Cholesky, CG, Multigrid };
    Method method = Method::Cholesky;
    double tolerance = 1e-10;
    int maxIterations = 10000;
    int iterations = 0;  // cg only: a fixed count, an approximation (never fails for not converging)
};

}  // namespace cloth
