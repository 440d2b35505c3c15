#pragma once
// The settings of the kinds exact and cg (exact.cpp): how the system is solved and to what
// tolerance. exact:method=multigrid runs the multigrid solver (multigrid_solver.cpp), which reads
// them too. Each field's key, with its doc, is in the kinds' tables (exact.cpp).

namespace cloth {

struct ExactSettings {
    enum class Method { Cholesky, CG, Multigrid };
    Method method = Method::Cholesky;
    double tolerance = 1e-10;
    int maxIterations = 10000;
    int iterations = 0;  // cg only: a fixed count, an approximation (never fails for not converging)
};

}  // namespace cloth
