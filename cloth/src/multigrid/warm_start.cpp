#include "warm_start.h"

#include <Eigen/Dense>
#include <algorithm>
#include <type_traits>

namespace cloth {

namespace {

// The coefficients c that minimize the energy norm of the error of x = sum_j c_j p_j, from the
// Gram matrix G_ij = p_i . W p_j and g_i = p_i . b: G c = g, by Cholesky with the vectors taken in
// order (newest first), and a vector dropped (c_j = 0) when what it adds beyond the ones kept has
// at most `drop` of its own energy (a vector the others nearly span would only amplify rounding).
Eigen::VectorXd energyCoefficients(const Eigen::MatrixXd& G, const Eigen::VectorXd& g, double drop) {
    const int k = int(g.size());
    std::vector<int> kept;
    Eigen::MatrixXd L = Eigen::MatrixXd::Zero(k, k);  // Cholesky factor of G over the kept vectors
    auto over = [&](const Eigen::VectorXd& v) {  // v's entries of the kept vectors
        Eigen::VectorXd o(kept.size());
        for (std::size_t a = 0; a < kept.size(); ++a) o[a] = v[kept[a]];
        return o;
    };
    for (int j = 0; j < k; ++j) {
        const int m = int(kept.size());
        const Eigen::VectorXd row = L.topLeftCorner(m, m).triangularView<Eigen::Lower>().solve(over(G.col(j)));
        const double pivot = G(j, j) - row.squaredNorm();
        if (!(pivot > drop * G(j, j))) continue;
        L.row(m).head(m) = row.transpose();
        L(m, m) = std::sqrt(pivot);
        kept.push_back(j);
    }
    const int m = int(kept.size());
    const auto Lk = L.topLeftCorner(m, m).triangularView<Eigen::Lower>();
    const Eigen::VectorXd ck = Lk.transpose().solve(Lk.solve(over(g)));
    Eigen::VectorXd c = Eigen::VectorXd::Zero(k);
    for (int a = 0; a < m; ++a) c[kept[a]] = ck[a];
    return c;
}

}  // namespace

template <class T>
double WarmStart<T>::start(Hierarchy<T>& h, Reductions& sums, double bNorm, std::vector<T>& x, std::vector<T>& r) {
    const Level<T>& L = h.level(0);
    ThreadPool& pool = sums.pool();
    int k = 0;
    while (size_ > 0 && k < int(history_.size()) && history_[k].size() == L.b.size()) ++k;
    x.assign(L.b.size(), T(0));
    r = L.b;
    if (k == 0) return 1;
    historyW_.resize(k);
    Eigen::MatrixXd G(k, k);
    Eigen::VectorXd g(k);
    for (int j = 0; j < k; ++j) {
        T* p = history_[j].data();
        pool.run(L.A.n, [&](int begin, int end) {
            for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q) p[q] *= L.active[q / 3];
        });
        h.product(0, history_[j], nullptr, historyW_[j]);
        g[j] = sums.dot(history_[j], L.b);
        for (int i = 0; i <= j; ++i) G(i, j) = G(j, i) = sums.dot(history_[i], historyW_[j]);
    }
    // float: keep the coefficients small enough that the rounding of r stays far below the
    // tolerances a float solve reaches
    const Eigen::VectorXd c = energyCoefficients(G, g, std::is_same_v<T, float> ? 1e-5 : 1e-10);
    for (int j = 0; j < k; ++j) {
        const T cj = T(c[j]);
        if (cj == T(0)) continue;
        const T *p = history_[j].data(), *q = historyW_[j].data();
        pool.run(L.A.n, [&](int begin, int end) {
            for (std::size_t e = 3 * std::size_t(begin); e < 3 * std::size_t(end); ++e) x[e] += cj * p[e], r[e] -= cj * q[e];
        });
    }
    return sums.norm(r) / bNorm;
}

template <class T>
void WarmStart<T>::remember(std::vector<T>& x) {
    if (size_ <= 0) return;
    if (int(history_.size()) < size_) history_.emplace_back();
    std::rotate(history_.rbegin(), history_.rbegin() + 1, history_.rend());
    history_[0].swap(x);
}

template class WarmStart<float>;
template class WarmStart<double>;

}  // namespace cloth
