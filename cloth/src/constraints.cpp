#include "cloth/constraints.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace cloth {

void Tethers::prepare(const Model& model, const std::vector<Pin>& pins) {
    const Index n = model.particleCount();
    std::vector<Index>& pinned = current_;
    pinned.clear();
    for (const Pin& p : pins)
        if (p.particle >= 0 && p.particle < n) pinned.push_back(p.particle);
    if (pinned == pinned_ && particles_ == n) return;
    pinned_ = pinned;
    particles_ = n;
    ++version_;
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

int Tethers::apply(const Model& model, const std::vector<Pin>& pins, Scalar maxStretch, Scalar h, State& state,
                   ThreadPool* pool, const std::vector<Index>* mayExceed) {
    prepare(model, pins);
    moved_.assign(free_.size(), 0);
    auto pullOne = [&](int k) {
        const Index i = free_[k];
        const Vec3 d = state.x.col(i) - state.x.col(anchor_[k]);
        const Scalar limit = (1 + maxStretch) * rest_[k], L2 = d.squaredNorm();
        moved_[std::size_t(k)] = !(L2 <= limit * limit);
        if (!moved_[std::size_t(k)]) return 0;  // most particles: no square root
        const Vec3 corr = (limit / std::sqrt(L2) - 1) * d;
        state.x.col(i) += corr;
        state.v.col(i) += corr / h;
        return 1;
    };
    if (mayExceed) {
        int moved = 0;
        for (const Index k : *mayExceed) moved += pullOne(k);
        return moved;
    }
    auto pull = [&](int begin, int end) {
        int moved = 0;
        for (int k = begin; k < end; ++k) moved += pullOne(k);
        return moved;
    };
    if (!pool) return pull(0, int(free_.size()));
    std::atomic<int> moved{0};
    pool->run(int(free_.size()), [&](int begin, int end) { moved += pull(begin, end); });
    return moved;
}

int ConstraintSet::apply(const Model& model, const std::vector<Pin>& pins, Scalar h, State& state, ThreadPool* pool,
                         const ConstraintHints* hints) {
    const int moved =
        settings_.tether > 0 ? tethers_.apply(model, pins, settings_.tether, h, state, pool, hints ? &hints->tethers : nullptr) : 0;
    if (settings_.stretchLimit <= 0) return moved;
    const SpringBits* mayExceed = hints ? &hints->springs : nullptr;
    if (mayExceed && moved > 0) {  // the springs of the particles the tethers moved, too
        const StretchLimit& limit = stretchLimit(model);
        mayExceed_ = *mayExceed;
        tethers_.forEachMoved([&](Index p) { limit.addSpringsOf(p, mayExceed_); });
        mayExceed = &mayExceed_;
    }
    const Index n = model.particleCount();
    pinned_.assign(n, 0);
    for (const Pin& p : pins)
        if (p.particle >= 0 && p.particle < n) pinned_[p.particle] = 1;
    return moved + stretch_.apply(model, pinned_, settings_.stretchLimit, settings_.stretchPasses, h, state, pool,
                                 mayExceed);
}

}  // namespace cloth
