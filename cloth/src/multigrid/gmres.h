#pragma once
// Flexible GMRES(m) (Saad 1993) on a system that the caller supplies as functions: for a system
// that is not symmetric (the step with the air fully coupled), preconditioned by the multigrid
// hierarchy of its symmetric part. Flexible: the preconditioner may change from one iteration to
// the next (a K-cycle is not a fixed linear operator), so the preconditioned directions are kept
// and the update is x += Z y. Restarted every `restart` iterations. Dot products run through
// Reductions: the same bits for any thread count.

#include <vector>

#include "krylov.h"
#include "reductions.h"

namespace cloth {

struct GmresControl {
    int restart = 30;
    int maxIterations = 100;
    double tolerance = 1e-3;  // relative residual |b - A x| / |b| to reach
};

class FlexibleGmres {
public:
    explicit FlexibleGmres(Reductions& sums) : sums_(sums) {}
    // Solves A x = b from x (system.apply: A, system.precondition: B ~ A^-1; system.converged is
    // not used). Returns the iterations; rel: the relative residual at the end (the recurrence's,
    // checked against a true residual at each restart).
    int solve(const KrylovSystem<double>& system, const GmresControl& control, const std::vector<double>& b,
              std::vector<double>& x, double& rel);

private:
    // One cycle of at most m iterations from x with residual r (|r| = beta); returns its iterations.
    int cycle(const KrylovSystem<double>& system, int m, double target, double beta, std::vector<double>& x,
              double& residual);
    Reductions& sums_;
    std::vector<std::vector<double>> v_, z_;  // the Arnoldi basis and its preconditioned directions
    std::vector<double> r_, w_;
    std::vector<double> h_, cs_, sn_, g_;  // Hessenberg (column-major, (m+1) x m), rotations, rhs
};

}  // namespace cloth
