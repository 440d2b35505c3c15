#include "gmres.h"

#include <cmath>

namespace cloth {

namespace {

void axpy(double a, const std::vector<double>& x, std::vector<double>& y) {
    for (std::size_t k = 0; k < y.size(); ++k) y[k] += a * x[k];
}

}  // namespace

int FlexibleGmres::cycle(const KrylovSystem<double>& system, int m, double target, double beta,
                         std::vector<double>& x, double& residual) {
    const std::size_t n = x.size();
    v_.resize(std::size_t(m) + 1), z_.resize(std::size_t(m));
    h_.assign(std::size_t(m + 1) * m, 0.0), cs_.assign(m, 0.0), sn_.assign(m, 0.0), g_.assign(std::size_t(m) + 1, 0.0);
    v_[0].resize(n);
    for (std::size_t k = 0; k < n; ++k) v_[0][k] = r_[k] / beta;
    g_[0] = beta;
    auto H = [&](int i, int j) -> double& { return h_[std::size_t(j) * (m + 1) + i]; };
    int j = 0;
    residual = beta;
    while (j < m && residual > target) {
        z_[j].resize(n);
        system.precondition(v_[j], z_[j]);
        system.apply(z_[j], w_);
        for (int i = 0; i <= j; ++i) {  // modified Gram-Schmidt
            H(i, j) = sums_.dot(w_, v_[i]);
            axpy(-H(i, j), v_[i], w_);
        }
        H(j + 1, j) = sums_.norm(w_);
        v_[j + 1].resize(n);
        const double scale = H(j + 1, j) > 0 ? 1 / H(j + 1, j) : 0;
        for (std::size_t k = 0; k < n; ++k) v_[j + 1][k] = w_[k] * scale;
        for (int i = 0; i < j; ++i) {  // the earlier rotations on the new column
            const double a = H(i, j), c = H(i + 1, j);
            H(i, j) = cs_[i] * a + sn_[i] * c;
            H(i + 1, j) = -sn_[i] * a + cs_[i] * c;
        }
        const double a = H(j, j), c = H(j + 1, j), d = std::hypot(a, c);
        cs_[j] = d > 0 ? a / d : 1, sn_[j] = d > 0 ? c / d : 0;
        H(j, j) = d, H(j + 1, j) = 0;
        g_[j + 1] = -sn_[j] * g_[j], g_[j] = cs_[j] * g_[j];
        residual = std::abs(g_[j + 1]);
        ++j;
        if (!(d > 0)) break;  // breakdown: A z = 0
    }
    std::vector<double> y(j, 0.0);  // H y = g by back substitution
    for (int i = j - 1; i >= 0; --i) {
        double s = g_[i];
        for (int k = i + 1; k < j; ++k) s -= H(i, k) * y[k];
        y[i] = H(i, i) != 0 ? s / H(i, i) : 0;
    }
    for (int i = 0; i < j; ++i) axpy(y[i], z_[i], x);
    return j;
}

int FlexibleGmres::solve(const KrylovSystem<double>& system, const GmresControl& control, const std::vector<double>& b,
                         std::vector<double>& x, double& rel) {
    const double bNorm = sums_.norm(b);
    if (!(bNorm > 0)) {
        x.assign(b.size(), 0.0);
        rel = 0;
        return 0;
    }
    r_.resize(b.size()), w_.resize(b.size());
    int iterations = 0;
    while (true) {
        system.apply(x, w_);
        for (std::size_t k = 0; k < b.size(); ++k) r_[k] = b[k] - w_[k];
        const double beta = sums_.norm(r_);
        rel = beta / bNorm;
        if (!(rel > control.tolerance) || iterations >= control.maxIterations) return iterations;
        const int m = std::min(control.restart, control.maxIterations - iterations);
        double residual = beta;
        const int done = cycle(system, m, control.tolerance * bNorm, beta, x, residual);
        iterations += done;
        if (done == 0) return iterations;
    }
}

}  // namespace cloth
