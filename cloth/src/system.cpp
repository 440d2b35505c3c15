#include "cloth/system.h"

#include "cloth/forces.h"

namespace cloth {

void applyOffDiagonal(const Model& model, const LinearSystem& sys, const Points& x, Points& y) {
    const Scalar h2 = sys.h * sys.h;
    const auto& springs = model.springs();
    y.setZero(3, model.particleCount());
    for (std::size_t s = 0; s < springs.size(); ++s) {
        const Spring& sp = springs[s];
        const bool pi = sys.pinned[sp.i], pj = sys.pinned[sp.j];
        if (pi || pj) continue;  // pinned columns live in the right-hand side, pinned rows are fixed
        y.col(sp.i) += h2 * (sys.springJ[s] * x.col(sp.j));
        y.col(sp.j) += h2 * (sys.springJ[s] * x.col(sp.i));
    }
}

Eigen::SparseMatrix<Scalar> assembleMatrix(const Model& model, const LinearSystem& sys) {
    const Index n = model.particleCount();
    const Scalar h2 = sys.h * sys.h;
    std::vector<Eigen::Triplet<Scalar>> t;
    t.reserve(9 * (n + 2 * model.springs().size()));
    auto block = [&t](Index bi, Index bj, const Mat3& B) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) t.emplace_back(3 * bi + r, 3 * bj + c, B(r, c));
    };
    for (Index i = 0; i < n; ++i) block(i, i, sys.diag[i]);
    const auto& springs = model.springs();
    for (std::size_t s = 0; s < springs.size(); ++s) {
        const Spring& sp = springs[s];
        if (sys.pinned[sp.i] || sys.pinned[sp.j]) continue;
        const Mat3 W = -h2 * sys.springJ[s];  // W_ij = -h^2 J_ij
        block(sp.i, sp.j, W);
        block(sp.j, sp.i, W.transpose());
    }
    Eigen::SparseMatrix<Scalar> W(3 * n, 3 * n);
    W.setFromTriplets(t.begin(), t.end());
    return W;
}

Scalar relativeResidual(const Model& model, const LinearSystem& sys, const Points& dv) {
    Points off;
    applyOffDiagonal(model, sys, dv, off);
    Scalar r2 = 0, b2 = 0;
    for (Index i = 0; i < model.particleCount(); ++i) {
        const Vec3 r = sys.diag[i] * dv.col(i) - off.col(i) - sys.rhs.col(i);
        r2 += r.squaredNorm();
        b2 += sys.rhs.col(i).squaredNorm();
    }
    return b2 > 0 ? std::sqrt(r2 / b2) : std::sqrt(r2);
}

}  // namespace cloth
