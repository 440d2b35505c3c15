#include "transfer.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

namespace cloth {

namespace {

using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor>;
using Strong = std::vector<std::vector<std::pair<int, double>>>;

// Linear interpolation from nc points to nf points over the same interval.
std::vector<std::vector<std::pair<int, double>>> interpolation1d(int nf, int nc) {
    std::vector<std::vector<std::pair<int, double>>> rows(nf);
    for (int c = 0; c < nf; ++c) {
        if (nc == nf) {
            rows[c] = {{c, 1.0}};
            continue;
        }
        const double t = double(c) * (nc - 1) / (nf - 1);
        const int c0 = std::min(int(std::floor(t)), nc - 2);
        const double fr = t - c0;
        if (1 - fr > 1e-12) rows[c].push_back({c0, 1 - fr});
        if (fr > 1e-12) rows[c].push_back({c0 + 1, fr});
    }
    return rows;
}

// Strong connections: -L_ij >= 0.25 max_k -L_ik (on a cloth mesh: edges, not the weaker bend springs).
Strong strongConnections(const SparseRows& L) {
    const int n = int(L.rows());
    Strong strong(n);
    for (int i = 0; i < n; ++i) {
        double maxOff = 0;
        for (SparseRows::InnerIterator it(L, i); it; ++it)
            if (it.col() != i) maxOff = std::max(maxOff, -it.value());
        for (SparseRows::InnerIterator it(L, i); it; ++it)
            if (it.col() != i && -it.value() >= 0.25 * maxOff && -it.value() > 0)
                strong[i].push_back({int(it.col()), -it.value()});
    }
    return strong;
}

// Each point's aggregate; `count` gets the number of aggregates.
std::vector<int> aggregates(const Strong& strong, int& count) {
    const int n = int(strong.size());
    std::vector<int> agg(n, -1);
    count = 0;
    for (int i = 0; i < n; ++i) {  // 1: a point whose strong neighbours are all free, with them
        if (agg[i] >= 0) continue;
        bool free = true;
        for (const auto& [j, w] : strong[i]) free = free && agg[j] < 0;
        if (!free) continue;
        agg[i] = count;
        for (const auto& [j, w] : strong[i]) agg[j] = count;
        ++count;
    }
    std::vector<int> joined = agg;
    for (int i = 0; i < n; ++i) {  // 2: the rest join their strongest aggregated neighbour
        if (agg[i] >= 0) continue;
        double best = 0;
        for (const auto& [j, w] : strong[i])
            if (agg[j] >= 0 && w > best) best = w, joined[i] = agg[j];
    }
    for (int i = 0; i < n; ++i)  // 3: isolated points are aggregates of their own
        if (joined[i] < 0) joined[i] = count++;
    return joined;
}

// The spectral radius of D^-1 Lf (Lf: the strong part of L with zero row sums) by power
// iteration, clamped to [1, 2].
double smootherRadius(const Strong& strong, const std::vector<double>& diag) {
    const int n = int(strong.size());
    Eigen::VectorXd x(n), y(n);
    for (int i = 0; i < n; ++i) x[i] = (i % 2 ? 1.0 : -1.0) + 0.1 * std::sin(double(i));
    double rho = 2;
    for (int it = 0; it < 30; ++it) {
        for (int i = 0; i < n; ++i) {
            double s = diag[i] * x[i];
            for (const auto& [j, w] : strong[i]) s -= w * x[j];
            y[i] = diag[i] > 0 ? s / diag[i] : 0.0;
        }
        rho = y.norm() / std::max(x.norm(), 1e-300);
        x = y / std::max(y.norm(), 1e-300);
    }
    return std::clamp(rho, 1.0, 2.0);
}

}  // namespace

Transfer Transfer::fromSparse(const SparseRows& P) {
    Transfer t;
    t.fine = int(P.rows());
    t.coarse = int(P.cols());
    auto fill = [](const auto& M, std::vector<int>& start, std::vector<int>& idx, std::vector<double>& w) {
        start.assign(1, 0);
        for (int r = 0; r < M.outerSize(); ++r) {
            for (typename std::decay_t<decltype(M)>::InnerIterator it(M, r); it; ++it)
                if (it.value() != 0) idx.push_back(int(it.col())), w.push_back(it.value());
            start.push_back(int(idx.size()));
        }
    };
    fill(P, t.pStart, t.pCol, t.pW);
    const SparseRows R = P.transpose();
    fill(R, t.rStart, t.rRow, t.rW);
    return t;
}

SparseRows Transfer::sparse() const {
    SparseRows Ps(fine, coarse);
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < fine; ++i)
        for (int e = pStart[i]; e < pStart[i + 1]; ++e) t.emplace_back(i, pCol[e], pW[e]);
    Ps.setFromTriplets(t.begin(), t.end());
    return Ps;
}

int coarserSide(int n) { return n <= 2 ? n : n / 2 + 1; }

Transfer gridTransfer(int nx, int ny, int cx, int cy) {
    const auto px = interpolation1d(nx, cx), py = interpolation1d(ny, cy);
    std::vector<Eigen::Triplet<double>> t;
    for (int r = 0; r < ny; ++r)
        for (int c = 0; c < nx; ++c)
            for (const auto& [R, wr] : py[r])
                for (const auto& [C, wc] : px[c]) t.emplace_back(r * nx + c, R * cx + C, wr * wc);
    SparseRows P(nx * ny, cx * cy);
    P.setFromTriplets(t.begin(), t.end());
    Transfer tr = Transfer::fromSparse(P);
    tr.label = std::to_string(cx) + "x" + std::to_string(cy);
    return tr;
}

// P = (I - omega D^-1 Lf) P_tent with omega = 4 / (3 rho).
Transfer aggregationTransfer(const SparseRows& L) {
    const Strong strong = strongConnections(L);
    const int n = int(L.rows());
    int count = 0;
    const std::vector<int> joined = aggregates(strong, count);
    std::vector<double> diag(n, 0.0);
    for (int i = 0; i < n; ++i)
        for (const auto& [j, w] : strong[i]) diag[i] += w;
    const double rho = smootherRadius(strong, diag);
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
        const double d = diag[i];
        if (d == 0) {
            t.emplace_back(i, joined[i], 1.0);
            continue;
        }
        const double s = 4.0 / (3.0 * rho) / d;
        t.emplace_back(i, joined[i], 1.0 - s * d);
        for (const auto& [j, w] : strong[i]) t.emplace_back(i, joined[j], s * w);
    }
    SparseRows P(n, count);
    P.setFromTriplets(t.begin(), t.end());
    P.prune(1e-14, 1);
    Transfer tr = Transfer::fromSparse(P);
    tr.label = std::to_string(count);
    return tr;
}

}  // namespace cloth
