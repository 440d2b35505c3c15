#include "bend_collapse.h"

#include <cstdlib>

#include "../simd.h"

namespace cloth {

namespace {

template <class T>
CLOTH_SIMD_CLONES void collapseBendRows(const BlockMatrix<T>& A, BlockMatrix<T>& S, const T* act, int nx, int begin,
                                        int end) {
    const int bx = A.bandOf(1), by = A.bandOf(nx), ox = A.bandOf(2), oy = A.bandOf(2 * nx);
    const int sx = S.bandOf(1), sy = S.bandOf(nx);
    for (int c = 0; c < 6; ++c) {
        const T *__restrict D = A.bandArray(0, c), *__restrict Bx = A.bandArray(bx, c), *__restrict By = A.bandArray(by, c);
        const T *__restrict Ox = A.bandArray(ox, c), *__restrict Oy = A.bandArray(oy, c);
        T *__restrict SD = S.bandArray(0, c), *__restrict Sx = S.bandArray(sx, c), *__restrict Sy = S.bandArray(sy, c);
CLOTH_IVDEP
        for (int i = begin; i < end; ++i) {
            SD[i] = act[i] * (D[i] - (Ox[i] + Ox[i - 2]) - T(4) * Ox[i - 1] - (Oy[i] + Oy[i - 2 * nx]) - T(4) * Oy[i - nx]);
            Sx[i] = act[i] * act[i + 1] * (Bx[i] + T(2) * (Ox[i] + Ox[i - 1]));
            Sy[i] = act[i] * act[i + nx] * (By[i] + T(2) * (Oy[i] + Oy[i - nx]));
        }
        for (const int d : {nx - 1, nx + 1})  // the shear bands, unchanged
            if (std::binary_search(S.offsets.begin(), S.offsets.end(), d))
                std::copy(A.bandArray(A.bandOf(d), c) + begin, A.bandArray(A.bandOf(d), c) + end,
                          S.bandArray(S.bandOf(d), c) + begin);
    }
}

// Whether the bands are those of a grid cloth with both bend bands.
bool gridBands(const std::vector<int>& offsets, int nx) {
    auto has = [&](int o) { return std::binary_search(offsets.begin(), offsets.end(), o); };
    if (nx < 5 || offsets.empty() || !has(1) || !has(2) || !has(nx) || !has(2 * nx)) return false;
    for (const int o : offsets)
        if (o != 1 && o != 2 && o != nx - 1 && o != nx && o != nx + 1 && o != 2 * nx) return false;
    return true;
}

}  // namespace

template <class T>
bool collapsePattern(const BlockMatrix<T>& A, const BandedSprings<T>& springs, int nx, BlockMatrix<T>& S) {
    const std::vector<int>& offsets = springs.offsets;  // = A.bandOffsets()
    if (!gridBands(offsets, nx)) return false;
    const int n = A.n;
    auto linked = [&A](int i, int j) {  // level 0's rows are in the model's order, not sorted
        return std::find(A.col.begin() + A.start[i], A.col.begin() + A.start[i + 1], j) != A.col.begin() + A.start[i + 1];
    };
    for (const int o : {2, 2 * nx}) {
        const std::size_t k = std::size_t(std::lower_bound(offsets.begin(), offsets.end(), o) - offsets.begin());
        for (int p = 0; p + o < n; ++p)
            if (springs.k[k * n + p] != T(0) && (!linked(p, p + o / 2) || !linked(p + o / 2, p + o))) return false;
    }
    S = BlockMatrix<T>{};
    S.n = n;
    S.start.assign(1, 0);
    for (int i = 0; i < n; ++i) {
        for (int e = A.start[i]; e < A.start[i + 1]; ++e) {
            const int o = std::abs(A.col[e] - i);
            if (o != 2 && o != 2 * nx) S.col.push_back(A.col[e]);
        }
        std::sort(S.col.begin() + S.start.back(), S.col.end());  // the order a plan then sums in
        S.start.push_back(int(S.col.size()));
    }
    std::vector<int> kept;
    for (const int o : offsets)
        if (o != 2 && o != 2 * nx) kept.push_back(o);
    S.numberSlotsByBand(kept);
    return true;
}

template <class T>
void collapseBends(const BlockMatrix<T>& A, const BandedSprings<T>& springs, int nx, BlockMatrix<T>& S,
                   ThreadPool& pool) {
    const T* act = springs.freeRow.data() + springs.pad;
    pool.run(A.n, [&](int begin, int end) {
        collapseBendRows(A, S, act, nx, begin, end);
        if (!S.blocks.empty()) S.copyBandsToBlocks(begin, end);  // a plan reads S
    });
}

template bool collapsePattern(const BlockMatrix<float>&, const BandedSprings<float>&, int, BlockMatrix<float>&);
template bool collapsePattern(const BlockMatrix<double>&, const BandedSprings<double>&, int, BlockMatrix<double>&);
template void collapseBends(const BlockMatrix<float>&, const BandedSprings<float>&, int, BlockMatrix<float>&,
                            ThreadPool&);
template void collapseBends(const BlockMatrix<double>&, const BandedSprings<double>&, int, BlockMatrix<double>&,
                            ThreadPool&);

}  // namespace cloth
