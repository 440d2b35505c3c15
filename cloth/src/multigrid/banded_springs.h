#pragma once
// The finest level of a grid cloth: its springs by band (slot p of band k joins particles p and
// p + o_k, as the bands of W hold W_{p, p + o_k}), so that the per-step passes run down
// contiguous arrays and vectorize, as the paper's stencil step does. A slot with no spring has
// k = 0 and contributes exact zeros. Positions, velocities and the free-row mask are
// structure-of-arrays with `pad` zeros on both sides.

#include <vector>

#include "cloth/model.h"
#include "cloth/thread_pool.h"
#include "fine_inputs.h"
#include "level.h"

namespace cloth {

template <class T>
struct BandedSprings {
    int n = 0, pad = 0;
    std::vector<int> offsets;
    std::vector<T> k, rest;          // band-major, n per band
    std::vector<double> xyz, vel;    // 3 arrays of n + 2 pad each
    std::vector<T> freeRow;          // n + 2 pad: 1 where the particle is free
    std::vector<T> bterm;            // 3 arrays per band of btStride, pad zeros first
    std::size_t btStride = 0;
    // The springs' blocks of W in the form the product reads: W_{i, i + o} = -h^2 (a I + b u u^T) =
    // -(c I + g g^T) with c = h^2 a and g = h sqrt(b) u (b >= 0; zero where an end is pinned or
    // there is no spring), four arrays per band (g0 g1 g2 c) of springStride, pad zeros first.
    // Four numbers a block instead of six: a product at 129x129 and larger streams W from memory.
    std::vector<T> spring;
    std::size_t springStride = 0;

    bool used() const { return !offsets.empty(); }
    std::size_t len() const { return std::size_t(n) + 2 * std::size_t(pad); }
    const double* x(int a) const { return xyz.data() + a * len() + pad; }
    const double* v(int a) const { return vel.data() + a * len() + pad; }
    T* bt(int band, int a) { return bterm.data() + (3 * std::size_t(band) + a) * btStride + pad; }
    const T* bt(int band, int a) const { return bterm.data() + (3 * std::size_t(band) + a) * btStride + pad; }
    T* sp(int band, int q) { return spring.data() + (4 * std::size_t(band) + q) * springStride + pad; }
    const T* sp(int band, int q) const { return spring.data() + (4 * std::size_t(band) + q) * springStride + pad; }

    // The cloth's springs by band, where A's pattern (the cloth's) can be banded; A's slots are
    // then renumbered band-major (slot k n + p: band k, row p, holes included). False: not banded.
    bool assign(const Model& cloth, BlockMatrix<T>& A);
};

// W and b of level 0 (the same as assembleGathered): the springs band by band and the row sums
// (W_ii = base + h^2 sum_j J_ij, eq. 12) in one pass, then the springs with a pinned end, then per
// row the terms of b without springs, the inverse diagonal, and empty rows for pinned particles.
template <class T>
void assembleBanded(BandedSprings<T>& B, const FineInputs<T>& in, Level<T>& L, ThreadPool& pool);

// out = b - W x (b given) or W x, rows [begin, end), for level 0 of a banded cloth: the diagonal
// band from W, the springs' blocks from their compact arrays S.
template <class T>
void springBandProduct(const BlockMatrix<T>& W, const BandedSprings<T>& S, const T* X0, const T* X1, const T* X2,
                       const T* b, T* out, int begin, int end);

}  // namespace cloth
