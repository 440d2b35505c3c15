#include "block_matrix.h"

#include <cstdlib>

#include "block_kernels.h"

namespace cloth {

namespace {

// Rows i... of b - W x (or W x without b) for the banded W: its diagonal band, then each band
// from the row's lower and upper side, in that order for every row.
template <class T, class V>
CLOTH_INLINE inline void bandedLanes(const BlockMatrix<T>& W, const T* X0, const T* X1, const T* X2, const T* b, T* out,
                                     int i) {
    V y0{}, y1{}, y2{};
    const std::size_t s = W.stride;
    const int bands = int(W.offsets.size());
    for (int k = 0; k <= bands; ++k) {
        const T* B = W.values.data() + 6 * std::size_t(k) * s + W.pad;
        for (const int side : {1, -1}) {
            if (k == 0 && side < 0) break;
            const int o = k == 0 ? 0 : W.offsets[k - 1];
            const int row = i + (side > 0 ? 0 : -o), col = i + side * o;
            addBlockTimes(B + row, B + s + row, B + 2 * s + row, B + 3 * s + row, B + 4 * s + row, B + 5 * s + row,
                          X0 + col, X1 + col, X2 + col, y0, y1, y2);
        }
    }
    storeRows(y0, y1, y2, b ? b + 3 * std::size_t(i) : nullptr, out + 3 * std::size_t(i));
}

template <class T>
CLOTH_SIMD_CLONES void bandedRows(const BlockMatrix<T>& W, const T* X0, const T* X1, const T* X2, const T* b, T* out,
                                  int begin, int end) {
    int i = begin;
    for (; i + kLanes<T> <= end; i += kLanes<T>) bandedLanes<T, Pack<T>>(W, X0, X1, X2, b, out, i);
    for (; i < end; ++i) bandedLanes<T, T>(W, X0, X1, X2, b, out, i);
}

}  // namespace

template <class T>
std::vector<int> BlockMatrix<T>::bandOffsets() const {
    // Banded needs one entry per (row, column): two springs between the same particles (a mesh
    // may have them) would share a band position.
    std::vector<int> all, row;
    for (int i = 0; i < n; ++i) {
        row.assign(col.begin() + start[i], col.begin() + start[i + 1]);
        std::sort(row.begin(), row.end());
        if (std::adjacent_find(row.begin(), row.end()) != row.end()) return {};
        for (int j : row)
            if (j > i) all.push_back(j - i);
    }
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    if (int(all.size()) > kMaxBands || n < 64) return {};
    return all;
}

template <class T>
void BlockMatrix<T>::layout(bool allowBands, bool keepBlocks) {
    offsets = allowBands ? bandOffsets() : std::vector<int>{};
    pad = 0;
    at.assign(std::size_t(n + slots), 0);
    if (offsets.empty()) {
        stride = 1;
        for (int b = 0; b < n + slots; ++b) at[b] = 6 * std::size_t(b);
        values.assign(6 * std::size_t(n + slots), T(0));
        blocks.clear();
        return;
    }
    pad = offsets.back();
    stride = spacedLength<T>(std::size_t(n + pad));
    for (int i = 0; i < n; ++i) {
        at[i] = pad + i;
        for (int e = start[i]; e < start[i + 1]; ++e)
            if (col[e] > i) at[n + slot[e]] = 6 * std::size_t(bandOf(col[e] - i)) * stride + pad + i;
    }
    values.assign(6 * (offsets.size() + 1) * stride, T(0));
    if (keepBlocks) blocks.assign(6 * std::size_t(n + slots), T(0));
    else blocks.clear();
}

template <class T>
void BlockMatrix<T>::numberSlots() {
    slots = 0;
    slot.assign(entries(), -1);
    for (int i = 0; i < n; ++i)
        for (int e = start[i]; e < start[i + 1]; ++e)
            if (col[e] > i) slot[e] = slots++;
    for (int i = 0; i < n; ++i)
        for (int e = start[i]; e < start[i + 1]; ++e)
            if (col[e] < i) slot[e] = slot[entryOf(col[e], i)];
}

template <class T>
void BlockMatrix<T>::numberSlotsByBand(const std::vector<int>& bandOffsets) {
    slot.assign(entries(), -1);
    for (int i = 0; i < n; ++i)
        for (int e = start[i]; e < start[i + 1]; ++e) {
            const int d = std::abs(col[e] - i);
            const int k = int(std::lower_bound(bandOffsets.begin(), bandOffsets.end(), d) - bandOffsets.begin());
            slot[e] = k * n + std::min(i, col[e]);
        }
    slots = int(bandOffsets.size()) * n;
}

template <class T>
void BlockMatrix<T>::copyBandsToBlocks(int begin, int end) {
    for (std::size_t k = 0; k <= offsets.size(); ++k) {
        const T* band = values.data() + 6 * k * stride + pad;
        T* copy = blocks.data() + 6 * (k == 0 ? 0 : std::size_t(n) * k);  // diagonal, then slot (k - 1) n + i
        for (int i = begin; i < end; ++i)
            for (int q = 0; q < 6; ++q) copy[6 * std::size_t(i) + q] = band[q * stride + i];
    }
}

template <class T>
Eigen::MatrixXd BlockMatrix<T>::dense() const {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    auto put = [&](int i, int j, int b) {
        const int idx[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) M(3 * i + r, 3 * j + c) += double(get(b, idx[r][c]));
    };
    for (int i = 0; i < n; ++i) {
        put(i, i, i);
        for (int e = start[i]; e < start[i + 1]; ++e) put(i, col[e], n + slot[e]);
    }
    return M;
}

template <class T>
void bandedProduct(const BlockMatrix<T>& W, const T* X0, const T* X1, const T* X2, const T* b, T* out, int begin,
                   int end) {
    bandedRows(W, X0, X1, X2, b, out, begin, end);
}

template <class T>
void blockProduct(const BlockMatrix<T>& A, const T* __restrict x, const T* __restrict b, T* __restrict out, int begin,
                  int end) {
    const int n = A.n;
    const int* __restrict start = A.start.data();
    const int* __restrict col = A.col.data();
    const int* __restrict slot = A.slot.data();
    const T* __restrict diag = A.values.data();
    const T* __restrict off = A.values.data() + 6 * std::size_t(n);  // gathered: block b at 6 b
    for (int i = begin; i < end; ++i) {
        const T* d = diag + 6 * std::size_t(i);
        const T* xi = x + 3 * std::size_t(i);
        T y0 = d[0] * xi[0] + d[1] * xi[1] + d[2] * xi[2];
        T y1 = d[1] * xi[0] + d[3] * xi[1] + d[4] * xi[2];
        T y2 = d[2] * xi[0] + d[4] * xi[1] + d[5] * xi[2];
        for (int e = start[i]; e < start[i + 1]; ++e) {
            const T* s = off + 6 * std::size_t(slot[e]);
            const T* xj = x + 3 * std::size_t(col[e]);
            const T q0 = xj[0], q1 = xj[1], q2 = xj[2];
            y0 += s[0] * q0 + s[1] * q1 + s[2] * q2;
            y1 += s[1] * q0 + s[3] * q1 + s[4] * q2;
            y2 += s[2] * q0 + s[4] * q1 + s[5] * q2;
        }
        T* o = out + 3 * std::size_t(i);
        if (b) {
            const T* bi = b + 3 * std::size_t(i);
            o[0] = bi[0] - y0, o[1] = bi[1] - y1, o[2] = bi[2] - y2;
        } else {
            o[0] = y0, o[1] = y1, o[2] = y2;
        }
    }
}

template struct BlockMatrix<float>;
template struct BlockMatrix<double>;
template void bandedProduct(const BlockMatrix<float>&, const float*, const float*, const float*, const float*, float*,
                            int, int);
template void bandedProduct(const BlockMatrix<double>&, const double*, const double*, const double*, const double*,
                            double*, int, int);
template void blockProduct(const BlockMatrix<float>&, const float*, const float*, float*, int, int);
template void blockProduct(const BlockMatrix<double>&, const double*, const double*, double*, int, int);

}  // namespace cloth
