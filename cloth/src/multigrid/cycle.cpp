#include "cycle.h"

#include "../kernels.h"

namespace cloth {

// Damped block Jacobi: x += omega W_ii^-1 (b - W x).
template <class T>
void Cycle<T>::smooth(Hierarchy<T>& h, int l, bool residualKnown) {
    Level<T>& L = h.level(l);
    if (!residualKnown) h.residual(l, L.x, L.b, L.r);
    const T omega = T(options_.damping);
    sums_.pool().run(L.A.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            T d[3];
            symmetricTimes(&L.dinv[6 * std::size_t(i)], &L.r[3 * std::size_t(i)], d);
            for (int a = 0; a < 3; ++a) L.x[3 * std::size_t(i) + a] += omega * d[a];
        }
    });
}

// b_c = P^T r; x_c = 0, so r_c = b_c.
template <class T>
void Cycle<T>::restrictResidual(Hierarchy<T>& h, int l) {
    Level<T>& L = h.level(l);
    Level<T>& C = h.level(l + 1);
    sums_.pool().run(C.A.n, [&](int begin, int end) {
        for (int I = begin; I < end; ++I) {
            T acc[3];
            L.P.gather(false, I, L.r.data(), acc);
            for (int a = 0; a < 3; ++a) {
                C.b[3 * std::size_t(I) + a] = acc[a];
                C.r[3 * std::size_t(I) + a] = acc[a];
                C.x[3 * std::size_t(I) + a] = T(0);
            }
        }
    });
}

// x += P x_c on rows with an unknown.
template <class T>
void Cycle<T>::prolongCorrection(Hierarchy<T>& h, int l) {
    Level<T>& L = h.level(l);
    const Level<T>& C = h.level(l + 1);
    sums_.pool().run(L.A.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            T acc[3];
            L.P.gather(true, i, C.x.data(), acc);
            for (int a = 0; a < 3; ++a) L.x[3 * std::size_t(i) + a] += L.active[i] * acc[a];
        }
    });
}

template <class T>
void Cycle<T>::run(Hierarchy<T>& h, int l, bool residualKnown) {
    if (l + 1 == h.size()) return h.solveCoarsest();
    Level<T>& L = h.level(l);
    for (int s = 0; s < options_.preSweeps; ++s) smooth(h, l, s == 0 && residualKnown);
    if (options_.preSweeps > 0 || !residualKnown) h.residual(l, L.x, L.b, L.r);
    restrictResidual(h, l);
    coarseSolve(h, l + 1);
    prolongCorrection(h, l);
    for (int s = 0; s < options_.postSweeps; ++s) smooth(h, l, false);
}

// c1 = B b, then c2 = B (b - t1 W c1), and x the combination of c1 and c2 that minimizes the
// W-norm of the error over their span.
template <class T>
void Cycle<T>::coarseSolve(Hierarchy<T>& h, int l) {
    if (l == 0 || l > options_.kcycleLevels || l + 1 == h.size()) return run(h, l, true);
    Level<T>& C = h.level(l);
    ThreadPool& pool = sums_.pool();
    C.kb = C.b;
    run(h, l, true);
    C.kc = C.x;
    h.product(l, C.kc, nullptr, C.kq);
    const double rho1 = sums_.dot(C.kc, C.kq);
    if (!(rho1 > 0)) return;  // c1 = 0: b = 0, and x = c1
    const double t1 = sums_.dot(C.kc, C.kb) / rho1;
    const T t1T = T(t1);
    pool.run(C.A.n, [&](int begin, int end) {
        for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q) {
            C.b[q] = C.r[q] = C.kb[q] - t1T * C.kq[q];
            C.x[q] = T(0);
        }
    });
    run(h, l, true);
    h.product(l, C.x, nullptr, C.kq2);
    const double gamma = sums_.dot(C.x, C.kq), beta = sums_.dot(C.x, C.kq2), alpha2 = sums_.dot(C.x, C.b);
    const double rho2 = beta - gamma * gamma / rho1;
    const bool second = rho2 > 1e-12 * beta;  // else c2 adds nothing independent of c1
    const T w1 = T(second ? t1 - gamma * alpha2 / (rho1 * rho2) : t1), w2 = T(second ? alpha2 / rho2 : 0.0);
    pool.run(C.A.n, [&](int begin, int end) {
        for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q) C.x[q] = w1 * C.kc[q] + w2 * C.x[q];
    });
}

template <class T>
template <class U>
void Cycle<T>::precondition(Hierarchy<T>& h, const std::vector<U>& r, std::vector<U>& z) {
    Level<T>& L = h.level(0);
    ThreadPool& pool = sums_.pool();
    z.resize(r.size());
    pool.run(L.A.n, [&](int begin, int end) {
        for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q)
            L.b[q] = L.r[q] = T(r[q]), L.x[q] = T(0);
    });
    run(h, 0, true);
    pool.run(L.A.n, [&](int begin, int end) {
        for (std::size_t q = 3 * std::size_t(begin); q < 3 * std::size_t(end); ++q) z[q] = U(L.x[q]);
    });
}

template class Cycle<float>;
template class Cycle<double>;
template void Cycle<float>::precondition(Hierarchy<float>&, const std::vector<float>&, std::vector<float>&);
template void Cycle<float>::precondition(Hierarchy<float>&, const std::vector<double>&, std::vector<double>&);
template void Cycle<double>::precondition(Hierarchy<double>&, const std::vector<double>&, std::vector<double>&);

}  // namespace cloth
