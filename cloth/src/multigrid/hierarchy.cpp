#include "hierarchy.h"

#include <Eigen/SparseCore>
#include <sstream>

#include "../kernels.h"
#include "bend_collapse.h"
#include "galerkin.h"

namespace cloth {

namespace {

using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// The scalar stiffness Laplacian that smoothed aggregation coarsens.
SparseRows stiffnessLaplacian(const Model& model) {
    std::vector<Eigen::Triplet<double>> t;
    for (const Spring& s : model.springs()) {
        t.emplace_back(s.i, s.j, -s.k), t.emplace_back(s.j, s.i, -s.k);
        t.emplace_back(s.i, s.i, s.k), t.emplace_back(s.j, s.j, s.k);
    }
    SparseRows lap(model.particleCount(), model.particleCount());
    lap.setFromTriplets(t.begin(), t.end());
    return lap;
}

}  // namespace

template <class T>
void Hierarchy<T>::prepare(const Model& model, FineSystem<T>& fine, const HierarchyOptions& options) {
    coarseAge_ = -1;
    levels_.clear();
    levels_.emplace_back();
    fine.prepare(model, levels_[0]);
    int nx = model.gridNx(), ny = model.gridNy();
    const bool geometric = !options.aggregation && nx > 0;
    std::ostringstream label;
    if (geometric) label << "geometric " << nx << "x" << ny;
    else label << "aggregation " << model.particleCount();
    const bool collapsed = geometric && collapsePattern(levels_[0].A, fine.band, nx, levels_[0].S);
    if (collapsed) levels_[0].bendNx = nx;
    SparseRows lap;
    if (!geometric) lap = stiffnessLaplacian(model);
    int byStencil = 0;
    bool done = false;
    while (!done && levels_.back().A.n > options.coarsestParticles) {
        const std::size_t before = levels_.size();
        addCoarseLevel(model, nx, ny, geometric, lap, options.stencilGalerkinMinRow, byStencil, done);
        if (levels_.size() > before) label << " " << levels_[before - 1].P.label;
    }
    label << " (Galerkin";
    if (collapsed) label << " with bend springs collapsed";
    if (byStencil > 0) label << "; by stencil on " << byStencil << " of " << levels_.size() - 1 << " coarse levels";
    label << ")";
    if (geometric && !collapsed)
        label << " (bend springs kept: level 0 is not a banded grid whose bend springs have both halves)";
    label_ = label.str();
    layoutLevels();
}

// The next coarser level: its transfer, its pattern and how its operator is computed (by stencil
// on nested grids, else by a plan). `done` when the last level coarsens no further.
template <class T>
void Hierarchy<T>::addCoarseLevel(const Model&, int& nx, int& ny, bool geometric, SparseRows& lap, int minRow,
                                  int& byStencil, bool& done) {
    const int fineNx = nx, fineNy = ny;
    if (geometric) {
        const int cx = coarserSide(nx), cy = coarserSide(ny);
        if (cx == nx && cy == ny) {
            done = true;
            return;
        }
        levels_.back().P = gridTransfer(nx, ny, cx, cy);
        nx = cx, ny = cy;
    } else {
        Transfer P = aggregationTransfer(lap);
        if (P.coarse >= levels_.back().A.n) {  // no coarsening left (every point its own aggregate)
            done = true;
            return;
        }
        const SparseRows Ps = P.sparse();
        lap = SparseRows(Ps.transpose() * lap * Ps);
        lap.prune(1e-12, 1);
        levels_.back().P = std::move(P);
    }
    levels_.emplace_back();
    Level<T>& fine = levels_[levels_.size() - 2];
    Level<T>& coarse = levels_.back();
    galerkinPattern(fine.source(), fine.P, coarse.A);
    if (geometric && fine.nested.build(fine.source(), coarse.A, fineNx, fineNy, minRow)) {
        ++byStencil;
        return;
    }
    fine.plan.build(fine.source(), fine.P, coarse.A);
}

// Each level's layout and vectors. The last level is factored, not multiplied; a plan reads its
// source level's block copy.
template <class T>
void Hierarchy<T>::layoutLevels() {
    for (Level<T>& L : levels_) {
        const bool planReads = !L.plan.empty();
        L.A.layout(&L != &levels_.back() || L.springs != nullptr, planReads && !L.bendNx);
        if (L.bendNx) L.S.layout(true, planReads);
        L.xStride = spacedLength<T>(std::size_t(L.A.n + 2 * L.A.pad));
        L.xs.assign(L.A.banded() ? 3 * L.xStride : 0, T(0));
        L.dinv.assign(6 * std::size_t(L.A.n), T(0));
        L.active.assign(L.A.n, T(0));
        for (auto* v : {&L.x, &L.b, &L.r}) v->assign(3 * std::size_t(L.A.n), T(0));
    }
}

// With one level the coarsest is the finest, which changes every step.
template <class T>
void Hierarchy<T>::refresh(const FineSystem<T>& fine, int coarseEvery) {
    const bool reuse = levels_.size() > 1 && coarseAge_ >= 0 && coarseAge_ + 1 < coarseEvery &&
                       fine.h2 == coarseH2_ && fine.compressionRule == coarseCompression_ &&
                       fine.pinned == coarsePinned_;
    if (reuse) {
        ++coarseAge_;
        return;
    }
    coarseOperators(fine);
    coarseAge_ = 0;
    coarsePinned_ = fine.pinned;
    coarseH2_ = fine.h2;
    coarseCompression_ = fine.compressionRule;
}

template <class T>
void Hierarchy<T>::coarseOperators(const FineSystem<T>& fine) {
    for (int l = 0; l + 1 < int(levels_.size()); ++l) galerkin(l, fine);
    factorCoarsest();
}

// Level l + 1's blocks from level l's (or, with bend springs collapsed, from its S), then its
// inverse diagonal blocks and free rows.
template <class T>
void Hierarchy<T>::galerkin(int l, const FineSystem<T>& fine) {
    Level<T>& F = levels_[l];
    if (F.bendNx) collapseBends(F.A, fine.band, F.bendNx, F.S, pool_);
    Level<T>& C = levels_[l + 1];
    if (!F.nested.empty()) F.nested.apply(F.source(), C.A, pool_);
    else F.plan.apply(F.source(), C.A, pool_);
    pool_.run(C.A.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            T D[6];
            for (int q = 0; q < 6; ++q) D[q] = C.A.get(i, q);
            // A row that no unknown reaches (all of its fine points pinned) is empty.
            C.active[i] = (D[0] + D[3] + D[5]) != T(0) ? T(1) : T(0);
            symmetricInverse(D, &C.dinv[6 * std::size_t(i)]);
        }
    });
}

template <class T>
void Hierarchy<T>::factorCoarsest() {
    const Level<T>& L = levels_.back();
    Eigen::MatrixXd M = L.A.dense();
    for (int i = 0; i < L.A.n; ++i)
        if (L.active[i] == T(0)) M.block<3, 3>(3 * i, 3 * i).setIdentity();
    coarsest_.compute(M);
    useFallback_ = coarsest_.info() != Eigen::Success;
    if (useFallback_) coarsestFallback_.compute(M);
}

template <class T>
void Hierarchy<T>::solveCoarsest() {
    Level<T>& L = levels_.back();
    Eigen::VectorXd b(3 * L.A.n);
    for (int q = 0; q < 3 * L.A.n; ++q) b[q] = double(L.b[q]) * double(L.active[q / 3]);
    const Eigen::VectorXd x = useFallback_ ? Eigen::VectorXd(coarsestFallback_.solve(b)) : Eigen::VectorXd(coarsest_.solve(b));
    for (int q = 0; q < 3 * L.A.n; ++q) L.x[q] = T(x[q]) * L.active[q / 3];
}

template <class T>
void Hierarchy<T>::product(int l, const std::vector<T>& x, const std::vector<T>* b, std::vector<T>& out) {
    Level<T>& L = levels_[l];
    const BlockMatrix<T>& A = L.A;
    out.resize(x.size());
    const T* bp = b ? b->data() : nullptr;
    if (!A.banded()) {
        pool_.run(A.n, [&](int begin, int end) { blockProduct(A, x.data(), bp, out.data(), begin, end); });
        return;
    }
    pool_.run(A.n, [&](int begin, int end) {
        T* X = L.xs.data() + A.pad;
        for (int i = begin; i < end; ++i)
            for (int a = 0; a < 3; ++a) X[a * L.xStride + i] = x[3 * std::size_t(i) + a];
    });
    const T* X = L.xs.data() + A.pad;
    pool_.run(A.n, [&](int begin, int end) {
        if (L.springs) springBandProduct(A, *L.springs, X, X + L.xStride, X + 2 * L.xStride, bp, out.data(), begin, end);
        else bandedProduct(A, X, X + L.xStride, X + 2 * L.xStride, bp, out.data(), begin, end);
    });
}

template class Hierarchy<float>;
template class Hierarchy<double>;

}  // namespace cloth
