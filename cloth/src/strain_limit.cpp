#include "cloth/strain_limit.h"

#include <atomic>
#include <cmath>

namespace cloth {

int limitStretch(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                 Scalar h, State& state, ThreadPool* pool) {
    const auto& mass = model.masses();
    const auto& springs = model.passSprings();
    const auto& start = model.passGroupStart();
    const Index blocks = model.passBlocks();
    // Each particle's share of a correction in position (1/m, 0 when pinned) and in velocity
    // (that / h), once per call rather than per correction: the same values, without four of the
    // five divisions a correction took.
    static thread_local std::vector<Scalar> weights;
    const Index n = model.particleCount();
    weights.resize(2 * std::size_t(n));
    for (Index p = 0; p < n; ++p) {
        const Scalar w = pinned[p] ? 0 : 1 / mass[p];
        weights[2 * std::size_t(p)] = w, weights[2 * std::size_t(p) + 1] = w / h;
    }
    // Springs [begin, end) in order; returns the corrections.
    Scalar* x = state.x.data();
    Scalar* v = state.v.data();
    const Scalar* weight = weights.data();  // a worker naming the thread_local would get its own
    const PassSpring* spring = springs.data();
    const Scalar scale = 1 + maxStretch;
    auto correct = [=](Index begin, Index end) {
        int count = 0;
        for (Index k = begin; k < end; ++k) {
            const PassSpring& s = spring[k];
            Scalar *xi = x + 3 * std::size_t(s.i), *xj = x + 3 * std::size_t(s.j);
            const Scalar dx = xj[0] - xi[0], dy = xj[1] - xi[1], dz = xj[2] - xi[2];
            // Most springs are within the limit: decide on squared lengths, without a square root
            // (a spring over by a rounding error of the square may be skipped: a correction of ulps).
            const Scalar limit = scale * s.rest, L2 = dx * dx + dy * dy + dz * dz;
            if (L2 <= limit * limit || L2 < Scalar(1e-24)) continue;
            const Scalar L = std::sqrt(L2);
            if (L <= limit) continue;
            const Scalar *wi = weight + 2 * std::size_t(s.i), *wj = weight + 2 * std::size_t(s.j);
            if (wi[0] + wj[0] == 0) continue;
            const Scalar f = (L - limit) / (L * (wi[0] + wj[0]));  // total shortening, split by 1/m
            const Scalar cx = f * dx, cy = f * dy, cz = f * dz;
            Scalar *vi = v + 3 * std::size_t(s.i), *vj = v + 3 * std::size_t(s.j);
            xi[0] += wi[0] * cx, xi[1] += wi[0] * cy, xi[2] += wi[0] * cz;
            xj[0] -= wj[0] * cx, xj[1] -= wj[0] * cy, xj[2] -= wj[0] * cz;
            vi[0] += wi[1] * cx, vi[1] += wi[1] * cy, vi[2] += wi[1] * cz;
            vj[0] -= wj[1] * cx, vj[1] -= wj[1] * cy, vj[2] -= wj[1] * cz;
            ++count;
        }
        return count;
    };
    int corrections = 0;
    for (int pass = 0; pass < passes; ++pass) {
        // The blocks (on the pool's threads, which never changes a bit: they share no particle),
        // then the seam.
        std::atomic<int> inBlocks{0};
        auto run = [&](int b0, int b1) {
            int count = 0;
            for (int b = b0; b < b1; ++b) count += correct(start[b], start[b + 1]);
            inBlocks += count;
        };
        if (pool && blocks > 1) pool->run(blocks, run);
        else run(0, blocks);
        const int thisPass = inBlocks + correct(start[blocks], start[blocks + 1]);
        corrections += thisPass;
        if (thisPass == 0) break;
    }
    return corrections;
}

int Tethers::apply(const Model& model, const std::vector<Pin>& pins, Scalar maxStretch, Scalar h, State& state,
                   ThreadPool* pool) {
    const Index n = model.particleCount();
    std::vector<Index> pinned;
    pinned.reserve(pins.size());
    for (const Pin& p : pins)
        if (p.particle >= 0 && p.particle < n) pinned.push_back(p.particle);
    if (pinned != pinned_ || particles_ != n) {
        pinned_ = pinned;
        particles_ = n;
        free_.clear(), anchor_.clear(), rest_.clear();
        std::vector<std::uint8_t> isPinned(n, 0);
        for (const Index p : pinned) isPinned[p] = 1;
        const Points& X = model.restPositions();
        for (Index i = 0; pinned.size() && i < n; ++i) {
            if (isPinned[i]) continue;
            Index best = pinned[0];
            Scalar best2 = (X.col(i) - X.col(best)).squaredNorm();
            for (const Index p : pinned) {  // the first of equally near pins: deterministic
                const Scalar d2 = (X.col(i) - X.col(p)).squaredNorm();
                if (d2 < best2) best = p, best2 = d2;
            }
            free_.push_back(i), anchor_.push_back(best), rest_.push_back(std::sqrt(best2));
        }
    }
    auto pull = [&](int begin, int end) {
        int moved = 0;
        for (int k = begin; k < end; ++k) {
            const Index i = free_[k];
            const Vec3 d = state.x.col(i) - state.x.col(anchor_[k]);
            const Scalar limit = (1 + maxStretch) * rest_[k], L2 = d.squaredNorm();
            if (L2 <= limit * limit) continue;  // most particles: no square root
            const Vec3 corr = (limit / std::sqrt(L2) - 1) * d;
            state.x.col(i) += corr;
            state.v.col(i) += corr / h;
            ++moved;
        }
        return moved;
    };
    if (!pool) return pull(0, int(free_.size()));
    std::atomic<int> moved{0};
    pool->run(int(free_.size()), [&](int begin, int end) { moved += pull(begin, end); });
    return moved;
}

}  // namespace cloth
