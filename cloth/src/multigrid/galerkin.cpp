#include "galerkin.h"

#include <utility>

namespace cloth {

namespace {

// fn(I, J, P_iI P_jJ) for every pair of P's entries in rows i and j.
template <class Fn>
void forPairs(const Transfer& P, int i, int j, Fn&& fn) {
    for (int a = P.pStart[i]; a < P.pStart[i + 1]; ++a)
        for (int b = P.pStart[j]; b < P.pStart[j + 1]; ++b) fn(P.pCol[a], P.pCol[b], P.pW[a] * P.pW[b]);
}

template <class T>
void symAxpy(T w, const T* s, T* out) {
    for (int k = 0; k < 6; ++k) out[k] += w * s[k];
}

}  // namespace

template <class T>
void galerkinPattern(const BlockMatrix<T>& src, const Transfer& P, BlockMatrix<T>& coarse) {
    const int nc = P.coarse, nf = src.n;
    std::vector<std::vector<int>> cols(nc);
    auto add = [&](int I, int J, double) {
        if (I != J) cols[I].push_back(J);
    };
    for (int i = 0; i < nf; ++i) {
        forPairs(P, i, i, add);
        for (int e = src.start[i]; e < src.start[i + 1]; ++e) forPairs(P, i, src.col[e], add);
    }
    coarse.n = nc;
    coarse.start.assign(1, 0);
    for (auto& c : cols) {
        std::sort(c.begin(), c.end());
        c.erase(std::unique(c.begin(), c.end()), c.end());
        coarse.col.insert(coarse.col.end(), c.begin(), c.end());
        coarse.start.push_back(int(coarse.col.size()));
    }
    coarse.numberSlots();
}

// The plan fills the diagonal and the slots from (I, J) with I < J; the fine matrix is symmetric,
// so the contributions with I > J are the same blocks mirrored.
template <class T>
void GalerkinPlan<T>::build(const BlockMatrix<T>& fine, const Transfer& P, const BlockMatrix<T>& coarse) {
    const int nc = coarse.n, nf = fine.n;
    std::vector<std::pair<int, int>> pairs;  // (dst, src)
    std::vector<double> weights;
    for (int i = 0; i < nf; ++i) {
        auto add = [&](int from) {
            return [&, from](int I, int J, double wt) {
                if (I > J) return;
                pairs.push_back({I == J ? I : nc + coarse.slot[coarse.entryOf(I, J)], from});
                weights.push_back(wt);
            };
        };
        forPairs(P, i, i, add(i));
        for (int e = fine.start[i]; e < fine.start[i + 1]; ++e) forPairs(P, i, fine.col[e], add(nf + fine.slot[e]));
    }
    const int dsts = nc + coarse.slots;
    start.assign(dsts + 1, 0);
    for (const auto& p : pairs) ++start[p.first + 1];
    for (int d = 0; d < dsts; ++d) start[d + 1] += start[d];
    std::vector<int> fillAt(start.begin(), start.end() - 1);
    src.resize(pairs.size());
    w.resize(pairs.size());
    for (std::size_t q = 0; q < pairs.size(); ++q) {
        const int at = fillAt[pairs[q].first]++;
        src[at] = pairs[q].second;
        w[at] = T(weights[q]);
    }
}

template <class T>
void GalerkinPlan<T>::apply(const BlockMatrix<T>& fine, BlockMatrix<T>& coarse, ThreadPool& pool) const {
    pool.run(coarse.n + coarse.slots, [&](int begin, int end) {
        for (int d = begin; d < end; ++d) {
            T acc[6] = {0, 0, 0, 0, 0, 0};
            for (int p = start[d]; p < start[d + 1]; ++p) symAxpy(w[p], fine.block(src[p]), acc);
            coarse.put(d, acc);
        }
    });
}

template void galerkinPattern(const BlockMatrix<float>&, const Transfer&, BlockMatrix<float>&);
template void galerkinPattern(const BlockMatrix<double>&, const Transfer&, BlockMatrix<double>&);
template struct GalerkinPlan<float>;
template struct GalerkinPlan<double>;

}  // namespace cloth
