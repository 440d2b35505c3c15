#include "cloth/strain_limit.h"

#include <cmath>

namespace cloth {

int limitStretch(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                 Scalar h, State& state) {
    const auto& mass = model.masses();
    int corrections = 0;
    for (int pass = 0; pass < passes; ++pass) {
        int thisPass = 0;
        for (const Spring& s : model.springs()) {
            const Vec3 d = state.x.col(s.j) - state.x.col(s.i);
            // Most springs are within the limit: decide on squared lengths, without a square root
            // (a spring over by a rounding error of the square may be skipped: a correction of ulps).
            const Scalar limit = (1 + maxStretch) * s.rest, L2 = d.squaredNorm();
            if (L2 <= limit * limit || L2 < Scalar(1e-24)) continue;
            const Scalar L = std::sqrt(L2);
            if (L <= limit) continue;
            const Scalar wi = pinned[s.i] ? 0 : 1 / mass[s.i], wj = pinned[s.j] ? 0 : 1 / mass[s.j];
            if (wi + wj == 0) continue;
            const Vec3 corr = (L - limit) / (L * (wi + wj)) * d;  // total shortening, split by 1/m
            state.x.col(s.i) += wi * corr;
            state.x.col(s.j) -= wj * corr;
            state.v.col(s.i) += (wi / h) * corr;
            state.v.col(s.j) -= (wj / h) * corr;
            ++thisPass;
        }
        corrections += thisPass;
        if (thisPass == 0) break;
    }
    return corrections;
}

int Tethers::apply(const Model& model, const std::vector<Pin>& pins, Scalar maxStretch, Scalar h, State& state) {
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
    int moved = 0;
    for (std::size_t k = 0; k < free_.size(); ++k) {
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
}

}  // namespace cloth
