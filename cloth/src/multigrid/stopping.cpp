#include "stopping.h"

#include <algorithm>

#include "../kernels.h"

namespace cloth {

template <class T>
bool StoppingTest::converged(double rel, const std::vector<T>& r, const std::vector<T>& x, const Level<T>& L,
                             Reductions& sums) const {
    if (rel > tolerance) return false;
    if (localTolerance <= 0) return true;
    const int n = L.A.n;
    auto squared = [](const T* v) { return double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]; };
    std::vector<double>& partial = sums.partial();
    partial.assign(2 * std::size_t(chunksOf(n)), 0.0);
    sums.pool().run(chunksOf(n), [&](int begin, int end) {
        for (int ch = begin; ch < end; ++ch) {
            double correction = 0, dv = 0;
            for (int i = ch * kChunk; i < std::min(n, (ch + 1) * kChunk); ++i) {
                T d[3];
                symmetricTimes(&L.dinv[6 * std::size_t(i)], &r[3 * std::size_t(i)], d);
                correction = std::max(correction, squared(d));
                dv = std::max(dv, squared(&x[3 * std::size_t(i)]));
            }
            partial[2 * std::size_t(ch)] = correction;
            partial[2 * std::size_t(ch) + 1] = dv;
        }
    });
    double correction = 0, dv = 0;
    for (std::size_t ch = 0; ch < partial.size(); ch += 2)
        correction = std::max(correction, partial[ch]), dv = std::max(dv, partial[ch + 1]);
    const double t = localTolerance;
    return correction <= t * t * dv;
}

template bool StoppingTest::converged(double, const std::vector<float>&, const std::vector<float>&,
                                      const Level<float>&, Reductions&) const;
template bool StoppingTest::converged(double, const std::vector<double>&, const std::vector<double>&,
                                      const Level<double>&, Reductions&) const;

}  // namespace cloth
