#include "cloth/exact_solve.h"

#include <Eigen/SparseCholesky>
#include <algorithm>

namespace cloth {

bool solveExact(const Model& model, const LinearSystem& sys, Points& dv, Scalar* residual, Scalar tolerance) {
    const Eigen::SparseMatrix<Scalar> W = assembleMatrix(model, sys);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<Scalar>> chol(W);
    if (chol.info() != Eigen::Success) return false;
    const Eigen::Map<const Eigen::VectorXd> b(sys.rhs.data(), sys.rhs.size());
    Eigen::VectorXd x = chol.solve(b);
    // Iterative refinement: a few residual corrections bring the relative residual to rounding
    // level even for ill-conditioned (stiff, small h) systems.
    const Scalar bNorm = std::max(b.norm(), Scalar(1e-300));
    Scalar rel = (W * x - b).norm() / bNorm;
    for (int k = 0; k < 3 && rel > std::min(tolerance, Scalar(1e-12)); ++k) {
        x += chol.solve(b - W * x);
        rel = (W * x - b).norm() / bNorm;
    }
    if (residual) *residual = rel;
    dv = Eigen::Map<const Points>(x.data(), 3, model.particleCount());
    return x.allFinite() && rel <= tolerance;
}

}  // namespace cloth
