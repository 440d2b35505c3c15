#pragma once
// The hierarchy: level 0 is the fine system, each coarser level has its operator W_c = P^T W P
// (Galerkin), the coarsest is factored. P is built once per model (transfer.h): bilinear on
// grids, smoothed aggregation on meshes. Coarse operators are rebuilt every `coarseEvery`
// solves, and reused in between while the pinned particles, h and the Jacobian rule stay the
// same (the finest level is always the current W, so a solve still reaches its tolerance on the
// current system; only the coarse correction lags).

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "cloth/model.h"
#include "cloth/thread_pool.h"
#include "fine_system.h"
#include "level.h"

namespace cloth {

struct HierarchyOptions {
    bool aggregation = false;        // smoothed aggregation on grids too (meshes always)
    int coarsestParticles = 16;      // coarsen until a level has at most this many
    int stencilGalerkinMinRow = 33;  // the Galerkin product by stencil from this many coarse points per row
};

template <class T>
class Hierarchy {
public:
    explicit Hierarchy(ThreadPool& pool) : pool_(pool) {}

    // The levels for `model`: level 0's pattern and springs (fine.prepare), then the transfers,
    // the coarse patterns and how each coarse operator is computed.
    void prepare(const Model& model, FineSystem<T>& fine, const HierarchyOptions& options);
    // The coarse operators and the coarsest factorization for fine's current system, unless the
    // last ones may be reused (coarseEvery).
    void refresh(const FineSystem<T>& fine, int coarseEvery);
    // Forget the coarse operators: the next refresh builds them.
    void invalidate() { coarseAge_ = -1; }

    int size() const { return int(levels_.size()); }
    Level<T>& level(int l) { return levels_[l]; }
    const Level<T>& level(int l) const { return levels_[l]; }
    // out = b - W_l x (b given) or W_l x.
    void product(int l, const std::vector<T>& x, const std::vector<T>* b, std::vector<T>& out);
    void residual(int l, const std::vector<T>& x, const std::vector<T>& b, std::vector<T>& r) { product(l, x, &b, r); }
    // The coarsest level's x from its b, by the dense factorization.
    void solveCoarsest();
    // "geometric 65x65 33x33 17x17 9x9 5x5 3x3 (Galerkin with bend springs collapsed; by stencil on 1 of 5 coarse levels)"
    const std::string& label() const { return label_; }

private:
    void addCoarseLevel(const Model& model, int& nx, int& ny, bool geometric, Eigen::SparseMatrix<double, Eigen::RowMajor>& lap,
                        int minRow, int& byStencil, bool& done);
    void layoutLevels();
    void coarseOperators(const FineSystem<T>& fine);
    void galerkin(int l, const FineSystem<T>& fine);
    void factorCoarsest();

    ThreadPool& pool_;
    std::vector<Level<T>> levels_;
    std::string label_;
    Eigen::LLT<Eigen::MatrixXd> coarsest_;
    Eigen::LDLT<Eigen::MatrixXd> coarsestFallback_;
    bool useFallback_ = false;
    int coarseAge_ = -1;  // solves since the coarse operators were built (-1: none for this model)
    std::vector<unsigned char> coarsePinned_;
    T coarseH2_ = 0;
    bool coarseCompression_ = true;
};

extern template class Hierarchy<float>;
extern template class Hierarchy<double>;

}  // namespace cloth
