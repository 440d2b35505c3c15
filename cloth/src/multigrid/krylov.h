#pragma once
// Preconditioned conjugate gradients on a system that the caller supplies as functions: its
// product, its preconditioner and its stopping test. Multigrid runs it with one cycle as the
// preconditioner; any caller with a symmetric positive definite system and a symmetric
// preconditioner can run it with the same hierarchy.

#include <functional>
#include <vector>

#include "reductions.h"

namespace cloth {

template <class T>
struct KrylovSystem {
    std::function<void(const std::vector<T>& x, std::vector<T>& out)> apply;        // out = W x
    std::function<void(const std::vector<T>& r, std::vector<T>& z)> precondition;   // z = B r
    // rel = |r| / |b|: whether x is good enough (asked only of an adaptive solve).
    std::function<bool(double rel, const std::vector<T>& r, const std::vector<T>& x)> converged;
};

struct KrylovControl {
    int maxIterations = 16;
    bool adaptive = true;   // false: exactly maxIterations (or until W p = 0)
    // A preconditioner that is not a fixed linear operator (a K-cycle, a cycle in float): the
    // flexible (Polak-Ribiere) beta keeps the directions conjugate.
    bool flexible = false;
    double bNorm = 1;
};

template <class T>
class ConjugateGradients {
public:
    explicit ConjugateGradients(Reductions& sums) : sums_(sums) {}
    // From x with r = b - W x and rel = |r| / |b|; returns the iterations, and rel at the end.
    int solve(const KrylovSystem<T>& system, const KrylovControl& control, std::vector<T>& x, std::vector<T>& r,
              double& rel);

private:
    Reductions& sums_;
    std::vector<T> z_, p_, q_;
};

extern template class ConjugateGradients<float>;
extern template class ConjugateGradients<double>;

}  // namespace cloth
