#include "compressed_springs.h"

#include "cloth/forces.h"

namespace cloth {

namespace {

// dJ of spring sp at x, and whether it is compressed (and long enough to have a direction).
bool compressedTerm(const Spring& sp, const Points& x, Mat3& dJ) {
    const Vec3 d = x.col(sp.j) - x.col(sp.i);
    const Scalar L = d.norm();
    if (!(L < sp.rest) || L < kMinSpringLength) return false;
    const Vec3 u = d / L;
    dJ = sp.k * (1 - sp.rest / L) * (Mat3::Identity() - u * u.transpose());
    return true;
}

}  // namespace

void CompressedSprings::clear() {
    springs_.clear();
    d_.clear();
    start_.clear();
    of_.clear();
}

void CompressedSprings::build(const Model& model, const Points& x, ThreadPool& pool) {
    const std::vector<Spring>& springs = model.springs();
    const int count = int(springs.size());
    all_.resize(springs.size());
    isCompressed_.resize(springs.size());
    pool.run(count, [&](int begin, int end) {
        for (int s = begin; s < end; ++s) {
            isCompressed_[s] = compressedTerm(springs[s], x, all_[s].dJ);
            all_[s].i = springs[s].i, all_[s].j = springs[s].j;
        }
    });
    springs_.clear();
    for (int s = 0; s < count; ++s)
        if (isCompressed_[s]) springs_.push_back(all_[s]);
    const Index n = model.particleCount();
    start_.assign(std::size_t(n) + 1, 0);
    for (const Entry& e : springs_) ++start_[e.i + 1], ++start_[e.j + 1];
    for (Index p = 0; p < n; ++p) start_[p + 1] += start_[p];
    of_.resize(std::size_t(start_[n]));
    std::vector<Index> next(start_.begin(), start_.end() - 1);
    for (Index c = 0; c < Index(springs_.size()); ++c) of_[next[springs_[c].i]++] = c, of_[next[springs_[c].j]++] = c;
}

void CompressedSprings::differences(const double* x, Scalar scale, ThreadPool& pool) {
    d_.resize(springs_.size());
    pool.run(int(springs_.size()), [&](int begin, int end) {
        for (int c = begin; c < end; ++c) {
            const Entry& e = springs_[c];
            d_[c] = scale * (e.dJ * (Vec3(x[3 * e.j], x[3 * e.j + 1], x[3 * e.j + 2]) -
                                     Vec3(x[3 * e.i], x[3 * e.i + 1], x[3 * e.i + 2])));
        }
    });
}

void CompressedSprings::subtractAt(Index p, double* y) const {
    if (start_.empty()) return;
    for (Index k = start_[p]; k < start_[p + 1]; ++k) {
        const Index c = of_[k];
        const Vec3& d = d_[c];
        if (springs_[c].i == p)
            for (int a = 0; a < 3; ++a) y[3 * p + a] -= d[a];
        else
            for (int a = 0; a < 3; ++a) y[3 * p + a] += d[a];
    }
}

}  // namespace cloth
