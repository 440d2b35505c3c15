#pragma once
// Transfers between levels: the prolongation P (coarse to fine) and its transpose, and the two
// ways of building P: bilinear interpolation between grids, and smoothed aggregation for meshes.

#include <Eigen/SparseCore>
#include <string>
#include <vector>

namespace cloth {

// P: fine rows -> coarse columns, kept both ways (prolongation by fine row, restriction by coarse
// row), so both are gathers that split across threads.
struct Transfer {
    int fine = 0, coarse = 0;
    std::vector<int> pStart, pCol, rStart, rRow;
    std::vector<double> pW, rW;
    std::string label;  // "17x17" or "aggregates 123"

    static Transfer fromSparse(const Eigen::SparseMatrix<double, Eigen::RowMajor>& P);
    Eigen::SparseMatrix<double, Eigen::RowMajor> sparse() const;

    // acc = sum over row I of P (prolong = true: fine row, coarse columns) or of P^T (restrict:
    // coarse row, fine columns) of w * src[3 col .. 3 col + 2].
    template <class A, class S>
    void gather(bool prolong, int row, const S* src, A acc[3]) const {
        const std::vector<int>& start = prolong ? pStart : rStart;
        const std::vector<int>& col = prolong ? pCol : rRow;
        const std::vector<double>& w = prolong ? pW : rW;
        acc[0] = acc[1] = acc[2] = A(0);
        for (int e = start[row]; e < start[row + 1]; ++e) {
            const A we = A(w[e]);
            const S* v = &src[3 * std::size_t(col[e])];
            acc[0] += we * v[0], acc[1] += we * v[1], acc[2] += we * v[2];
        }
    }
};

// The side of the next coarser grid: about half the points over the same interval.
int coarserSide(int n);
// Bilinear interpolation from a cx x cy grid to an nx x ny grid over the same rectangle (any
// sizes; 2^k + 1 sides nest exactly).
Transfer gridTransfer(int nx, int ny, int cx, int cy);
// Smoothed aggregation from a scalar stiffness Laplacian L (zero row sums): greedy aggregates over
// the strong connections, a piecewise constant tentative P, one damped-Jacobi smoothing of it.
Transfer aggregationTransfer(const Eigen::SparseMatrix<double, Eigen::RowMajor>& L);

}  // namespace cloth
