#pragma once
// The structural springs of a grid as chains, for xpbd: every row (from the pinned column out)
// and every column of the grid is a chain of compliant distance constraints, projected at once
// by one tridiagonal solve of its linearized system (Thomas' algorithm), as in direct
// position-based solvers for rods (Deul et al. 2018). A pass of Gauss-Seidel moves a correction
// one spring along; a chain's solve carries it to the chain's end, so the tension of a 33-particle
// row reaches the pole in one pass.
//
// For a chain of particles q_0..q_m and links C_k = |x_{q_k+1} - x_{q_k}| - l_k with unit
// directions n_k, the step solves (J W J^T + alphaTilde) dLambda = -C - alphaTilde lambda, where
// (J W J^T)_kk = w_k + w_k+1 and (J W J^T)_k,k+1 = -w_k+1 (n_k . n_k+1), then moves
// x_{q_k} += w_k (n_k-1 dLambda_k-1 - n_k dLambda_k).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cloth/model.h"

namespace cloth {

class XpbdChains {
public:
    // The model's rows and columns as chains of its structural springs; none when the model is not
    // a grid. Springs not in a chain are left to Gauss-Seidel (isChained false).
    void build(const Model& model);
    bool isChained(std::size_t spring) const { return spring < chained_.size() && chained_[spring]; }
    // One projection of every chain (rows, then columns) at step h; lambda and x as xpbd keeps them.
    void project(const Model& model, const std::vector<Scalar>& weight, Scalar h, std::vector<Scalar>& lambda,
                 Scalar* x);

private:
    void projectChain(const Model& model, std::size_t chain, const std::vector<Scalar>& weight, Scalar h,
                      std::vector<Scalar>& lambda, Scalar* x);

    std::uint64_t model_ = 0;
    std::vector<std::size_t> start_;      // chain c: links start_[c] .. start_[c + 1]
    std::vector<std::size_t> springs_;    // the links' springs, in chain order
    std::vector<Index> particles_, next_;  // link k joins particles_[k] and next_[k]
    std::vector<char> chained_;
    std::vector<Scalar> diag_, off_, rhs_, dLambda_;  // the tridiagonal system of one chain
    std::vector<Vec3> dir_;
};

}  // namespace cloth
