#include "cloth/constraints.h"

#include "simd.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <cmath>

namespace cloth {

namespace {

// What the pass reads of a spring to decide whether it is over its limit: where its ends'
// coordinates start in the positions (3 i, 3 j), and the squared length at or under which it is
// left alone: its limit squared, or just under 1e-24 (no direction to pull along) when that is
// larger. One compare per spring instead of two products and two compares.
using Check = StretchLimit::Check;

struct PassArgs {
    const Check* check;
    const PassSpring* spring;
    Scalar* x;
    Scalar* v;
    const Scalar* m;
    const std::uint8_t* fixed;
    Scalar scale, h;
    std::int64_t* movedAt;  // StretchLimit::movedAt_
    std::int64_t stamp;     // this pass's (StretchLimit::stamps_)
    std::int64_t checked;   // the previous pass's stamp; in the first, one older than any: every spring is checked
};

// Springs [begin, end) in order (Gauss-Seidel); returns the corrections. After the first pass, a
// spring whose ends have not moved since the previous pass checked it (at checked + k) is within
// its limit, as that check found.
CLOTH_SIMD_CLONES int correctRange(const PassArgs& a, Index begin, Index end) {
    Scalar* x = a.x;
    Scalar* v = a.v;
    std::int64_t* movedAt = a.movedAt;
    const std::int64_t checked = a.checked;
    int count = 0;
    for (Index k = begin; k < end; ++k) {
        const Check& c = a.check[k];
        if (movedAt[c.xi] < checked + k && movedAt[c.xj] < checked + k) continue;
        Scalar *xi = x + c.xi, *xj = x + c.xj;
        const Scalar dx = xj[0] - xi[0], dy = xj[1] - xi[1], dz = xj[2] - xi[2];
        // Most springs are within the limit: decide on squared lengths, without a square root
        // (a spring over by a rounding error of the square may be skipped: a correction of ulps).
        const Scalar L2 = dx * dx + dy * dy + dz * dz;
        if (L2 <= c.within) continue;
        const PassSpring& s = a.spring[k];
        const Scalar limit = a.scale * s.rest, L = std::sqrt(L2);
        if (L <= limit) continue;
        const Scalar wi = a.fixed[s.i] ? 0 : 1 / a.m[s.i], wj = a.fixed[s.j] ? 0 : 1 / a.m[s.j];
        if (wi + wj == 0) continue;
        const Scalar f = (L - limit) / (L * (wi + wj));  // total shortening, split by 1/m
        const Scalar cx = f * dx, cy = f * dy, cz = f * dz, ai = wi / a.h, aj = wj / a.h;
        Scalar *vi = v + c.xi, *vj = v + c.xj;
        xi[0] += wi * cx, xi[1] += wi * cy, xi[2] += wi * cz;
        xj[0] -= wj * cx, xj[1] -= wj * cy, xj[2] -= wj * cz;
        vi[0] += ai * cx, vi[1] += ai * cy, vi[2] += ai * cz;
        vj[0] -= aj * cx, vj[1] -= aj * cy, vj[2] -= aj * cz;
        movedAt[c.xi] = movedAt[c.xj] = a.stamp + k;
        ++count;
    }
    return count;
}

}  // namespace

int StretchLimit::apply(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                        Scalar h, State& state, ThreadPool* pool) {
    const auto& springs = model.passSprings();
    const auto& start = model.passGroupStart();
    const Index blocks = model.passBlocks();
    const Scalar scale = 1 + maxStretch;
    if (model_ != model.id() || maxStretch_ != maxStretch) {  // the checks, found again
        const Scalar floor = std::nextafter(Scalar(1e-24), Scalar(0));
        check_.resize(springs.size());
        for (std::size_t k = 0; k < springs.size(); ++k) {
            const Scalar limit = scale * springs[k].rest;
            check_[k] = {3 * springs[k].i, 3 * springs[k].j, std::max(limit * limit, floor)};
        }
        model_ = model.id(), maxStretch_ = maxStretch;
    }
    if (movedAt_.size() != std::size_t(3 * model.particleCount())) movedAt_.assign(std::size_t(3 * model.particleCount()), -1);
    const auto count = std::int64_t(springs.size());
    PassArgs args{check_.data(), springs.data(), state.x.data(), state.v.data(), model.masses().data(),
                  pinned.data(), scale, h, movedAt_.data(), stamps_, std::numeric_limits<std::int64_t>::min() / 2};
    stamps_ += std::int64_t(passes) * count;  // what is left in movedAt_ is older than any stamp of a later call
    auto correct = [&](Index begin, Index end) { return correctRange(args, begin, end); };
    int corrections = 0;
    for (int pass = 0; pass < passes; ++pass) {
        if (pass > 0) args.checked = args.stamp, args.stamp += count;
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
    std::vector<Index>& pinned = current_;
    pinned.clear();
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

int ConstraintSet::apply(const Model& model, const std::vector<Pin>& pins, Scalar h, State& state, ThreadPool* pool) {
    const int moved = settings_.tether > 0 ? tethers_.apply(model, pins, settings_.tether, h, state, pool) : 0;
    if (settings_.stretchLimit <= 0) return moved;
    const Index n = model.particleCount();
    pinned_.assign(n, 0);
    for (const Pin& p : pins)
        if (p.particle >= 0 && p.particle < n) pinned_[p.particle] = 1;
    return moved + stretch_.apply(model, pinned_, settings_.stretchLimit, settings_.stretchPasses, h, state, pool);
}

}  // namespace cloth
