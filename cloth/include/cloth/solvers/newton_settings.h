#pragma once
// The settings of the solver kind `newton` (src/solvers/newton.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(NewtonSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct NewtonSettings {
    static constexpr const char* kKind = "newton";
    enum class Integrator { BackwardEuler, BDF2, Midpoint };
    Integrator integrator = Integrator::BackwardEuler;
    double theta = 0.5;
    int maxIterations = 8;
    double tolerance = 1e-3;
    double linearTolerance = 1e-2;
    bool coupledAir = true;
    int threads = 1;
};

}  // namespace cloth
