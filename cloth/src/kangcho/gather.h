#pragma once
// The Kang & Cho step in the gather layout, for any mesh: the same linearized backward Euler
// system and the same Jacobi iterations as the reference (system.cpp + jacobiSweep), computed
// without 3x3 blocks per spring and gathered per particle instead of scattered per spring:
//  - a spring's Jacobian block is J = a I + b u u^T (eq. 16; eq. 17 clamps l0/L to 1), so a
//    spring stores u, a, b and its force magnitude: 6 numbers instead of 9 + 3;
//  - every particle sums over its own springs (CSR adjacency), so particles split across threads
//    with no write conflicts, and the result does not depend on the split;
//  - W_ii is inverted in closed form (symmetric 3x3) and kept as 6 numbers.
// T is the working precision (float or double); the state stays double.

#include <memory>
#include <vector>

#include "kangcho/layout.h"

namespace cloth {

template <class T>
class GatherKangCho final : public KangChoLayout {
public:
    using KangChoLayout::KangChoLayout;
    void solve(const StepProblem& problem, int iterations, Points& dv, double* forcesMs) override;

private:
    void prepare(const Model& model);
    void setPins(const State& state, const StepInput& input);
    void computeSprings(const State& state, bool compressionRule);
    void assembleParticles(const Environment& env, const State& state, const StepInput& input);
    void jacobiSweeps(T h2, int iterations);
    int n_ = 0, springs_ = 0;
    // Topology, per adjacency entry: spring, other end, sign of u as seen from this particle.
    std::vector<int> adjStart_, adjSpring_, adjOther_;
    std::vector<T> adjSign_;
    std::vector<int> si_, sj_;
    std::vector<T> k_, rest_, mass_;
    // Per step.
    std::vector<T> ux_, uy_, uz_, a_, b_, fm_;    // per spring
    std::vector<T> rhs_, winv_, dvA_, dvB_, pin_; // 3n, 6n, 3n, 3n, 3n
    std::vector<unsigned char> pinned_;
};

extern template class GatherKangCho<float>;
extern template class GatherKangCho<double>;

}  // namespace cloth
