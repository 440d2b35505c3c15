#include "solvers/xpbd_chains.h"

#include <cmath>

#include "cloth/forces.h"

namespace cloth {

void XpbdChains::build(const Model& model) {
    model_ = model.id();
    start_.assign(1, 0);
    springs_.clear(), particles_.clear(), next_.clear();
    chained_.assign(model.springs().size(), 0);
    const Index nx = model.gridNx(), ny = model.gridNy();
    if (nx < 2 || ny < 2) return;
    // link[p * 2 + 0]: the structural spring from p to its right neighbour, [p * 2 + 1]: below.
    std::vector<std::size_t> link(std::size_t(2 * nx * ny), model.springs().size());
    for (std::size_t s = 0; s < model.springs().size(); ++s) {
        const Spring& sp = model.springs()[s];
        if (sp.kind != SpringKind::Structural) continue;
        if (sp.j == sp.i + 1 && sp.i % nx + 1 < nx) link[std::size_t(2 * sp.i)] = s;
        else if (sp.j == sp.i + nx) link[std::size_t(2 * sp.i + 1)] = s;
    }
    auto add = [&](Index first, Index step, Index links, int side) {
        for (Index k = 0; k < links; ++k) {
            const Index p = first + k * step;
            const std::size_t s = link[std::size_t(2 * p + side)];
            if (s == model.springs().size()) return;  // not a full grid: this chain stays Gauss-Seidel's
        }
        for (Index k = 0; k < links; ++k) {
            const Index p = first + k * step;
            const std::size_t s = link[std::size_t(2 * p + side)];
            springs_.push_back(s), particles_.push_back(p), next_.push_back(p + step), chained_[s] = 1;
        }
        start_.push_back(springs_.size());
    };
    for (Index r = 0; r < ny; ++r) add(r * nx, 1, nx - 1, 0);  // rows, from column 0 (the pole's) out
    for (Index c = 0; c < nx; ++c) add(c, nx, ny - 1, 1);      // columns, from the top down
}

void XpbdChains::project(const Model& model, const std::vector<Scalar>& weight, Scalar h, std::vector<Scalar>& lambda,
                         Scalar* x) {
    if (model_ != model.id()) build(model);
    for (std::size_t c = 0; c + 1 < start_.size(); ++c) projectChain(model, c, weight, h, lambda, x);
}

void XpbdChains::projectChain(const Model& model, std::size_t chain, const std::vector<Scalar>& weight, Scalar h,
                              std::vector<Scalar>& lambda, Scalar* x) {
    const std::size_t begin = start_[chain], m = start_[chain + 1] - begin;
    diag_.resize(m), off_.resize(m), rhs_.resize(m), dLambda_.resize(m), dir_.resize(m);
    for (std::size_t k = 0; k < m; ++k) {  // the links' directions, constraints and diagonal
        const std::size_t s = springs_[begin + k];
        const Spring& sp = model.springs()[s];
        const Index a = particles_[begin + k], b = next_[begin + k];
        const Vec3 d = Vec3(x[3 * b], x[3 * b + 1], x[3 * b + 2]) - Vec3(x[3 * a], x[3 * a + 1], x[3 * a + 2]);
        const Scalar L = d.norm();
        const bool live = sp.k > 0 && L >= kMinSpringLength;
        const Scalar alpha = live ? 1 / (sp.k * h * h) : 0;
        dir_[k] = live ? Vec3(d / L) : Vec3::Zero();
        diag_[k] = live ? weight[a] + weight[b] + alpha : 1;
        rhs_[k] = live ? -(L - sp.rest + alpha * lambda[s]) : 0;
    }
    for (std::size_t k = 0; k + 1 < m; ++k) off_[k] = -weight[next_[begin + k]] * dir_[k].dot(dir_[k + 1]);
    for (std::size_t k = 1; k < m; ++k) {  // Thomas: eliminate below the diagonal
        const Scalar f = off_[k - 1] / diag_[k - 1];
        diag_[k] -= f * off_[k - 1];
        rhs_[k] -= f * rhs_[k - 1];
    }
    for (std::size_t k = m; k-- > 0;)
        dLambda_[k] = (rhs_[k] - (k + 1 < m ? off_[k] * dLambda_[k + 1] : 0)) / diag_[k];
    for (std::size_t k = 0; k < m; ++k) {
        lambda[springs_[begin + k]] += dLambda_[k];
        const Index a = particles_[begin + k], b = next_[begin + k];
        const Vec3 move = dLambda_[k] * dir_[k];
        for (int c = 0; c < 3; ++c) x[3 * a + c] -= weight[a] * move[c], x[3 * b + c] += weight[b] * move[c];
    }
}

}  // namespace cloth
