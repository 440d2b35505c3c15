#include "gathered_springs.h"

#include "../kernels.h"

namespace cloth {

template <class T>
void SpringSet<T>::assign(const Model& m) {
    const auto& springs = m.springs();
    const int S = m.springCount();
    si.resize(S), sj.resize(S), k.resize(S), rest.resize(S);
    for (int s = 0; s < S; ++s)
        si[s] = springs[s].i, sj[s] = springs[s].j, k[s] = T(springs[s].k), rest[s] = T(springs[s].rest);
    pinnedJ.assign(6 * std::size_t(S), T(0));
    adjSpring = m.adjSpring();
    adjSign.resize(adjSpring.size());
    for (int p = 0; p < m.particleCount(); ++p)
        for (int e = m.adjStart()[p]; e < m.adjStart()[p + 1]; ++e)
            adjSign[e] = springs[adjSpring[e]].i == p ? T(1) : T(-1);
}

template <class T>
void SpringSet<T>::compute(const FineInputs<T>& in, BlockMatrix<T>& W, ThreadPool& pool) {
    const double *xs = in.xs, *vs = in.vs;
    const T h = in.h, h2 = in.h2;
    bterm.resize(3 * si.size());
    pool.run(int(si.size()), [&](int begin, int end) {
        for (int s = begin; s < end; ++s) {
            const int i = si[s], j = sj[s];
            const SpringTerms<T> t = springTerms(T(xs[3 * j] - xs[3 * i]), T(xs[3 * j + 1] - xs[3 * i + 1]),
                                                 T(xs[3 * j + 2] - xs[3 * i + 2]), k[s], rest[s], in.compressionRule);
            T J[6];
            jacobianOf(t, J);
            const bool pinnedEnd = in.pinned[i] || in.pinned[j];
            if (pinnedEnd) std::copy(J, J + 6, &pinnedJ[6 * std::size_t(s)]);
            const T scale = pinnedEnd ? T(0) : -h2;
            T O[6];
            for (int q = 0; q < 6; ++q) O[q] = scale * J[q];
            W.put(W.n + s, O);
            const T dq[3] = {T(vs[3 * j] - vs[3 * i]), T(vs[3 * j + 1] - vs[3 * i + 1]), T(vs[3 * j + 2] - vs[3 * i + 2])};
            T Jq[3];
            symmetricTimes(J, dq, Jq);
            bterm[3 * std::size_t(s)] = h * t.fm * t.ux + h2 * Jq[0];
            bterm[3 * std::size_t(s) + 1] = h * t.fm * t.uy + h2 * Jq[1];
            bterm[3 * std::size_t(s) + 2] = h * t.fm * t.uz + h2 * Jq[2];
        }
    });
}

namespace {

// Row i of a free particle: K = W_ii and r = b_i.
template <class T>
void gatherRow(const SpringSet<T>& S, const FineInputs<T>& in, const BlockMatrix<T>& A, int i, T K[6], T r[3]) {
    const T h2 = in.h2;
    for (int e = A.start[i]; e < A.start[i + 1]; ++e) {
        const int s = A.slot[e], j = A.col[e];
        if (in.pinned[j]) {  // the stored block is zero; the diagonal still has the spring
            const T* J = &S.pinnedJ[6 * std::size_t(s)];
            for (int q = 0; q < 6; ++q) K[q] += h2 * J[q];
            T Jq[3];
            symmetricTimes(J, &in.pinDv[3 * std::size_t(j)], Jq);
            for (int a = 0; a < 3; ++a) r[a] += h2 * Jq[a];
        } else {
            const T* O = A.block(A.n + s);
            for (int q = 0; q < 6; ++q) K[q] -= O[q];
        }
        for (int a = 0; a < 3; ++a) r[a] += S.adjSign[e] * S.bterm[3 * std::size_t(s) + a];
    }
    for (int q = 0; q < 6; ++q) K[q] += in.base[6 * std::size_t(i) + q];
}

}  // namespace

template <class T>
void assembleGathered(const SpringSet<T>& S, const FineInputs<T>& in, Level<T>& L, ThreadPool& pool) {
    pool.run(L.A.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            T* dinv = &L.dinv[6 * std::size_t(i)];
            T* bi = &L.b[3 * std::size_t(i)];
            if (in.pinned[i]) {
                const T zero[6] = {0, 0, 0, 0, 0, 0};
                L.A.put(i, zero);
                for (int q = 0; q < 6; ++q) dinv[q] = T(0);
                bi[0] = bi[1] = bi[2] = T(0);
                L.active[i] = T(0);
                continue;
            }
            L.active[i] = T(1);
            T K[6] = {0, 0, 0, 0, 0, 0}, r[3] = {0, 0, 0};
            gatherRow(S, in, L.A, i, K, r);
            L.A.put(i, K);
            symmetricInverse(K, dinv);
            in.rows.add(i, r);
            bi[0] = r[0], bi[1] = r[1], bi[2] = r[2];
        }
    });
}

template struct SpringSet<float>;
template struct SpringSet<double>;
template void assembleGathered(const SpringSet<float>&, const FineInputs<float>&, Level<float>&, ThreadPool&);
template void assembleGathered(const SpringSet<double>&, const FineInputs<double>&, Level<double>&, ThreadPool&);

}  // namespace cloth
