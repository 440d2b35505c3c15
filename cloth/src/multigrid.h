#pragma once
// Multigrid for the linearized backward Euler system that every implicit solver here reads
// (system.h: W dv = b, J with eq. 17, W_ii with drag and implicit air, pinned particles
// eliminated). One V-cycle:
//   level l: nu1 damped block-Jacobi sweeps (the paper's eq. 11 sweep, damped by omega),
//            r = b - W x, b_c = P^T r, coarse solve (recursively), x += P x_c, nu2 sweeps;
//   coarsest: a dense Cholesky solve.
// A K-cycle level (MultigridSettings::kcycleLevels; by default level 1 when adaptive) makes its
// coarse solve two flexible CG iterations, each preconditioned by one cycle from there.
// Coarse operators are Galerkin, W_c = P^T W P, rebuilt every step: on a grid whose sides are both
// odd (17x17, 33x33, ...: the coarse grid keeps every other point) and whose coarse rows are long
// enough (MultigridSettings::stencilGalerkinMinRow), one dimension at a time, each a fixed list
// of shifted bands, the same for every row ("by stencil"); otherwise from a plan computed once per model (which
// fine block, with which weight, lands in which coarse block). On a grid, level 0's product reads
// S rather than W: W with each bend spring (i, i + 2) replaced by two springs over its halves
// with twice its block (MultigridSettings::collapseBend), so every coarse level has the 9-point
// stencil; the smoother, the residuals and CG use W itself.
// Prolongation P (built once per model):
//   grids     bilinear interpolation from a grid of about half the points per side over the same
//             rectangle (any nx, ny: 33x22 and 40x27 work; 2^k+1 sizes nest exactly);
//   meshes    smoothed aggregation: greedy aggregates over the strong springs, piecewise constant
//             tentative P, one damped-Jacobi smoothing of it with the stiffness Laplacian.
// Adaptive solves start from the previous step's dv (MultigridSettings::start), where that leaves
// a smaller residual than zero does: on the study's vehicle path it saves 15-38% of the cycles.
// Pinned particles are unknowns fixed at zero in the iteration (their prescribed dv is already in
// their neighbours' b, as in the paper's step), so their rows are zero, the prolongation does not
// reach them, and P^T W P is the Galerkin operator of the free particles.
// Mixed precision (MultigridSettings::floatCycles): the double solve keeps a float hierarchy too,
// whose level 0 is its own W rounded, and each CG iteration's cycle runs there, on the residual
// rounded to float.
// Every loop runs over rows (or coarse rows) split across threads, and every sum over rows runs
// in fixed chunks in a fixed order: the result is bit-identical for any thread count.

#include <Eigen/Dense>
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "cloth/solver.h"
#include "cloth/thread_pool.h"

namespace cloth {

// MultigridSettings: cloth/solver.h.

struct MultigridStats {
    int cycles = 0;  // cycles applied (with conjugate gradients: CG iterations, one cycle each)
    double residual = -1;  // relative residual |b - W dv| / |b| over free particles (-1: not computed)
};

// A sparse symmetric matrix of symmetric 3x3 blocks (6 numbers each: xx xy xz yy yz zz).
// Row i's off-diagonal entries are e in [start[i], start[i + 1]), in column col[e], with their block
// in slot[e]: W_ij = W_ji, so the two entries of a pair share one slot (on level 0, a slot is a
// spring). Block b (b < n: the diagonal block of row b; b = n + s: slot s) keeps its six numbers at
// values[at[b] + q * stride], q = 0..5, in one of two layouts:
//   gathered  block after block (stride 1);
//   banded    for a matrix with few distinct column offsets j - i (a grid cloth has 6 in row-major
//             order: 1, 2, nx - 1, nx, nx + 1, 2 nx; its Galerkin coarse grids 12): by diagonals.
//             Band k holds W_{i, i + o_k} (o_0 = 0, then the offsets o_k > 0) of every row i as six
//             arrays over rows, zero where the row has no such entry, so that a product runs down
//             the bands and vectorizes over rows; W_{i, i - o} = W_{i - o, i} reads the same arrays
//             shifted (rows -pad .. -1 of every array are zero). Where a Galerkin plan reads the
//             level, the blocks are kept a second time, block after block (`blocks`): the plan
//             visits them by index, and there a block's six numbers share a cache line instead of
//             lying in six arrays (at 129x129 the plan took 1.9x less time).
template <class T>
struct BlockMatrix {
    static constexpr int kMaxBands = 24;
    int n = 0, slots = 0;
    std::vector<int> start, col, slot;
    std::vector<T> values;
    std::vector<T> blocks;        // banded and read by a plan: block b's six numbers again at 6 b (else empty)
    std::vector<std::size_t> at;  // n + slots
    std::size_t stride = 1;
    std::vector<int> offsets;     // banded: o_1 < o_2 < ...; empty: gathered
    int pad = 0;

    int entries() const { return int(col.size()); }
    // The entry of (i, j) in row i's sorted columns, or -1 if the pattern has none.
    int entryOf(int i, int j) const {
        const auto b = col.begin() + start[i], e = col.begin() + start[i + 1];
        const auto it = std::lower_bound(b, e, j);
        return it != e && *it == j ? int(it - col.begin()) : -1;
    }
    bool banded() const { return !offsets.empty(); }
    // The pattern's distinct column offsets j - i > 0 if it can be banded (one entry per row and
    // column, at most kMaxBands offsets, n >= 64), else empty.
    std::vector<int> bandOffsets() const;
    // Chooses the layout (banded where the pattern allows and allowBands; with the block copy if
    // keepBlocks) and zeroes the values.
    void layout(bool allowBands, bool keepBlocks);
    // One slot per pair (i < j), shared with (j, i), for the pattern in start and col.
    void numberSlots();
    // Or band-major for the band offsets o_1 < o_2 < ... (bandOffsets()): slot k n + i for the pair
    // (i, i + o_{k+1}), holes included, so that the block copy of a band is contiguous
    // (copyBandsToBlocks).
    void numberSlotsByBand(const std::vector<int>& bandOffsets);
    // Banded with band-major slots and the block copy kept: rows [begin, end) of every band into
    // the copy.
    void copyBandsToBlocks(int begin, int end);
    // Block b's six numbers, contiguous (gathered, or banded with the block copy).
    const T* block(int b) const { return banded() ? &blocks[6 * std::size_t(b)] : &values[6 * std::size_t(b)]; }
    T get(int b, int q) const { return values[at[b] + q * stride]; }
    // Sets block b (in the layout, and in `blocks` when kept).
    void put(int b, const T* v) {
        T* o = &values[at[b]];
        for (int q = 0; q < 6; ++q) o[q * stride] = v[q];
        if (!blocks.empty()) std::copy(v, v + 6, &blocks[6 * std::size_t(b)]);
    }
    Eigen::MatrixXd dense() const;  // for tests
};

template <class T>
class Multigrid {
public:
    // Worker threads: `pool`, or (null) a pool of settings.threads of its own.
    explicit Multigrid(const MultigridSettings& settings, std::shared_ptr<ThreadPool> pool = nullptr);
    ~Multigrid();

    // Builds the system at `state` and solves it; dv gets the pinned particles' prescribed change.
    // Returns false when the result is not finite. forcesMs: time of the system build.
    bool solve(const Model& model, const Environment& env, const State& state, const StepInput& input,
               bool compressionRule, Points& dv, MultigridStats& stats, double* forcesMs = nullptr);

    // The hierarchy's pieces, for tests and diagnostics (valid after solve or prepareSystem).
    void prepareSystem(const Model& model, const Environment& env, const State& state, const StepInput& input,
                       bool compressionRule);
    int levels() const;
    const BlockMatrix<T>& matrix(int level) const;
    Eigen::MatrixXd prolongation(int level) const;  // dense P from level + 1 to level
    // One cycle from x = 0 for the right-hand side b (3n, particle-major); returns x.
    Eigen::VectorXd vcycle(const Eigen::VectorXd& b);
    // What coarse level `level` hands back to the finer one for its right-hand side b (3 n_level,
    // in the level's point order): one cycle from there, or on a K-cycle level
    // (MultigridSettings::kcycleLevels) two flexible CG iterations each preconditioned by one.
    // Level 0: vcycle(b).
    Eigen::VectorXd coarseSolve(int level, const Eigen::VectorXd& b);
    // "geometric 65x65 33x33 17x17 9x9 5x5 3x3 (Galerkin with bend springs collapsed; by stencil on 1 of 5 coarse levels)"
    std::string describeHierarchy() const;

private:
    template <class>
    friend class Multigrid;  // the double solve keeps a float one for its cycles (floatCycles)
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

extern template class Multigrid<float>;
extern template class Multigrid<double>;

}  // namespace cloth
