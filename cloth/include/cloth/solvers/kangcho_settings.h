#pragma once
// The settings of the solver kind `kangcho` (src/solvers/kangcho.cpp): a public struct with its defaults,
// filled in by code (`SolverConfig(KangchoSettings{...})`) or from text and JSON through the kind's keys,
// each documented once in its key table (`cloth_run --solver-table` prints them).

namespace cloth {

struct KangchoSettings {
    static constexpr const char* kKind = "kangcho";
    int iterations = 1;
    // fast: the stencil layout when the springs form a few constant index offsets (grids), else
    // the gather; gather: always the gather; reference: the paper's step as written.
    enum class Impl { Fast, Gather, Reference };
    Impl impl = Impl::Fast;
    int threads = 1;
    bool singlePrecision = false;
};

}  // namespace cloth
