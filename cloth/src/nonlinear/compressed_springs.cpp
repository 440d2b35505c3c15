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

void CompressedSprings::clear() { springs_.clear(); }

void CompressedSprings::build(const Model& model, const Points& x, ThreadPool& pool) {
    springs_.clear();
    if (pool.threads() == 1) {
        Mat3 dJ;
        for (const Spring& sp : model.springs())
            if (compressedTerm(sp, x, dJ)) springs_.push_back({sp.i, sp.j, dJ});
        return;
    }
    collect(model, x, pool);
    listByParticle(model.particleCount());
}

// The compressed springs in their order, each spring's test and dJ split among the threads.
void CompressedSprings::collect(const Model& model, const Points& x, ThreadPool& pool) {
    const std::vector<Spring>& springs = model.springs();
    all_.resize(springs.size());
    isCompressed_.resize(springs.size());
    pool.run(int(springs.size()), [&](int begin, int end) {
        for (int s = begin; s < end; ++s) isCompressed_[s] = compressedTerm(springs[s], x, all_[s]);
    });
    for (std::size_t s = 0; s < springs.size(); ++s)
        if (isCompressed_[s]) springs_.push_back({springs[s].i, springs[s].j, all_[s]});
}

void CompressedSprings::listByParticle(Index n) {
    start_.assign(std::size_t(n) + 1, 0);
    for (const Entry& e : springs_) ++start_[e.i + 1], ++start_[e.j + 1];
    for (Index p = 0; p < n; ++p) start_[p + 1] += start_[p];
    of_.resize(std::size_t(start_[n]));
    std::vector<Index> next(start_.begin(), start_.end() - 1);
    for (Index c = 0; c < Index(springs_.size()); ++c)
        of_[next[springs_[c].i]++] = 2 * c, of_[next[springs_[c].j]++] = 2 * c + 1;
}

Vec3 CompressedSprings::term(const Entry& e, const double* x, Scalar scale) const {
    return scale * (e.dJ * (Vec3(x[3 * e.j], x[3 * e.j + 1], x[3 * e.j + 2]) -
                            Vec3(x[3 * e.i], x[3 * e.i + 1], x[3 * e.i + 2])));
}

void CompressedSprings::subtract(const double* x, Scalar scale, const std::vector<std::uint8_t>& pinned, double* y,
                                 ThreadPool& pool) {
    if (springs_.empty()) return;
    if (pool.threads() == 1) {
        for (const Entry& e : springs_) {
            if (pinned[e.i] && pinned[e.j]) continue;
            const Vec3 d = term(e, x, scale);
            for (int a = 0; a < 3; ++a) {
                if (!pinned[e.i]) y[3 * e.i + a] -= d[a];
                if (!pinned[e.j]) y[3 * e.j + a] += d[a];
            }
        }
        return;
    }
    d_.resize(springs_.size());
    pool.run(int(springs_.size()), [&](int begin, int end) {
        for (int c = begin; c < end; ++c) d_[c] = term(springs_[c], x, scale);
    });
    pool.run(int(start_.size()) - 1, [&](int begin, int end) {
        for (Index p = begin; p < end; ++p) {
            if (pinned[p]) continue;
            for (Index k = start_[p]; k < start_[p + 1]; ++k) {
                const Vec3& d = d_[of_[k] / 2];
                for (int a = 0; a < 3; ++a) y[3 * p + a] += of_[k] % 2 == 0 ? -d[a] : d[a];
            }
        }
    });
}

}  // namespace cloth
