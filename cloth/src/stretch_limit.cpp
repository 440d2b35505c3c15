// The stretch limit's passes (cloth/constraints.h): Gauss-Seidel over the springs to check, as bits.

#include "cloth/constraints.h"

#include "simd.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace cloth {

namespace {

// What the pass reads of a spring to decide whether it is over its limit: where its ends'
// coordinates start in the positions (3 i, 3 j), and the squared length at or under which it is
// left alone: its limit squared, or just under 1e-24 (no direction to pull along) when that is
// larger. One compare per spring instead of two products and two compares.
using Check = StretchLimit::Check;
using Word = std::atomic<std::uint64_t>;

struct PassArgs {
    const Check* check;
    const PassSpring* spring;
    Scalar* x;
    Scalar* v;
    const Scalar* m;
    const std::uint8_t* fixed;
    Scalar scale, h;
    const Index *springStart, *springsOf;  // StretchLimit's per-particle springs
    Word* marked;                          // a marking pass's springs to check
    std::int64_t* movedAt;                 // StretchLimit::movedAt_
    std::int64_t stamp;                    // this pass's (StretchLimit::stamps_)
    std::int64_t checked;  // the previous pass's stamp; in the first, one older than any: every spring is checked
};

// The first spring in [from, end) whose bit is set, or end.
Index nextSet(const Word* bits, Index from, Index end) {
    if (from >= end) return end;
    std::size_t w = std::size_t(from) / 64;
    const std::size_t last = std::size_t(end - 1) / 64;
    std::uint64_t word = bits[w].load(std::memory_order_relaxed) & (~std::uint64_t(0) << (from % 64));
    while (word == 0) {
        if (++w > last) return end;
        word = bits[w].load(std::memory_order_relaxed);
    }
    return std::min(end, Index(w * 64 + std::size_t(std::countr_zero(word))));
}

// Sets bit k; Shared: other threads set bits of the same words (a locked or), else a plain one.
template <bool Shared>
void set(Word* bits, Index k) {
    Word& w = bits[std::size_t(k) / 64];
    const std::uint64_t bit = std::uint64_t(1) << (k % 64);
    if constexpr (Shared) w.fetch_or(bit, std::memory_order_relaxed);
    else w.store(w.load(std::memory_order_relaxed) | bit, std::memory_order_relaxed);
}

// Particle p moved at spring k of a marking pass: its springs after k are checked later in it.
template <bool Shared>
void markLater(const PassArgs& a, Index p, Index k) {
    for (Index e = a.springStart[p + 1] - 1; e >= a.springStart[p] && a.springsOf[e] > k; --e)
        set<Shared>(a.marked, a.springsOf[e]);
}

// Spring k pulled back to its limit if it is over; whether it was.
CLOTH_INLINE inline bool corrected(const PassArgs& a, Index k) {
    const Check& c = a.check[k];
    Scalar *xi = a.x + c.xi, *xj = a.x + c.xj;
    const Scalar dx = xj[0] - xi[0], dy = xj[1] - xi[1], dz = xj[2] - xi[2];
    // Most springs are within the limit: decide on squared lengths, without a square root (a
    // spring over by a rounding error of the square may be skipped: a correction of ulps).
    const Scalar L2 = dx * dx + dy * dy + dz * dz;
    if (L2 <= c.within) return false;
    const PassSpring& s = a.spring[k];
    const Scalar limit = a.scale * s.rest, L = std::sqrt(L2);
    if (L <= limit) return false;
    const Scalar wi = a.fixed[s.i] ? 0 : 1 / a.m[s.i], wj = a.fixed[s.j] ? 0 : 1 / a.m[s.j];
    if (wi + wj == 0) return false;
    const Scalar f = (L - limit) / (L * (wi + wj));  // total shortening, split by 1/m
    const Scalar cx = f * dx, cy = f * dy, cz = f * dz, ai = wi / a.h, aj = wj / a.h;
    Scalar *vi = a.v + c.xi, *vj = a.v + c.xj;
    xi[0] += wi * cx, xi[1] += wi * cy, xi[2] += wi * cz;
    xj[0] -= wj * cx, xj[1] -= wj * cy, xj[2] -= wj * cz;
    vi[0] += ai * cx, vi[1] += ai * cy, vi[2] += ai * cz;
    vj[0] -= aj * cx, vj[1] -= aj * cy, vj[2] -= aj * cz;
    a.movedAt[c.xi] = a.movedAt[c.xj] = a.stamp + k;
    return true;
}

// Springs [begin, end) in order (Gauss-Seidel), each checked when an end moved since the previous
// pass checked it (at checked + k); returns the corrections.
CLOTH_SIMD_CLONES int scanRange(const PassArgs& a, Index begin, Index end) {
    int count = 0;
    for (Index k = begin; k < end; ++k) {
        const Check& c = a.check[k];
        if (a.movedAt[c.xi] < a.checked + k && a.movedAt[c.xj] < a.checked + k) continue;
        count += corrected(a, k);
    }
    return count;
}

// The marked springs of [begin, end) in order; returns the corrections. Shared: other threads run
// other ranges at the same time.
template <bool Shared>
int markRange(const PassArgs& a, Index begin, Index end) {
    int count = 0;
    for (Index k = nextSet(a.marked, begin, end); k < end; k = nextSet(a.marked, k + 1, end)) {
        if (!corrected(a, k)) continue;
        markLater<Shared>(a, a.spring[k].i, k), markLater<Shared>(a, a.spring[k].j, k);
        ++count;
    }
    return count;
}

// A pass marks rather than scans when the pass before corrected fewer than 1 / kDense of the
// springs (its marks cost some twenty bits a correction, a scan a few loads a spring).
constexpr int kDense = 32;

}  // namespace

void StretchLimit::prepare(const Model& model, Scalar maxStretch) {
    if (model_ == model.id() && maxStretch_ == maxStretch) return;
    const auto& springs = model.passSprings();
    const Scalar scale = 1 + maxStretch, floor = std::nextafter(Scalar(1e-24), Scalar(0));
    check_.resize(springs.size());
    for (std::size_t k = 0; k < springs.size(); ++k) {
        const Scalar limit = scale * springs[k].rest;
        check_[k] = {3 * springs[k].i, 3 * springs[k].j, std::max(limit * limit, floor)};
    }
    const Index n = model.particleCount();
    springStart_.assign(std::size_t(n) + 1, 0);
    for (const PassSpring& s : springs) ++springStart_[std::size_t(s.i) + 1], ++springStart_[std::size_t(s.j) + 1];
    for (Index p = 0; p < n; ++p) springStart_[std::size_t(p) + 1] += springStart_[std::size_t(p)];
    springsOf_.resize(std::size_t(springStart_.back()));
    std::vector<Index> fill(springStart_.begin(), springStart_.end() - 1);
    for (Index k = 0; k < Index(springs.size()); ++k) {  // in increasing k per particle
        const PassSpring& s = springs[std::size_t(k)];
        springsOf_[std::size_t(fill[std::size_t(s.i)]++)] = k, springsOf_[std::size_t(fill[std::size_t(s.j)]++)] = k;
    }
    words_ = (springs.size() + 63) / 64;
    marked_ = std::make_unique<Word[]>(words_);
    movedAt_.assign(std::size_t(3 * n), -1);
    model_ = model.id(), maxStretch_ = maxStretch;
}

void StretchLimit::addSpringsOf(Index particle, SpringBits& bits) const {
    for (Index e = springStart_[std::size_t(particle)]; e < springStart_[std::size_t(particle) + 1]; ++e)
        addSpring(bits, springsOf_[std::size_t(e)]);
}

// A marking pass's springs: the caller's, or those of the particles that moved at or after
// `movedSince` (the pass before: every spring with an end moved since it was checked, and more).
// False, to scan instead, when the caller lists more than 1 / kDense of the springs.
bool StretchLimit::markedFrom(const SpringBits* mayExceed, std::int64_t movedSince) {
    if (mayExceed) {
        std::size_t listed = 0;
        for (std::uint64_t w : *mayExceed)
            for (; w != 0; w &= w - 1) ++listed;  // a few bits in most words
        if (listed * kDense > check_.size()) return false;
        for (std::size_t w = 0; w < words_; ++w) marked_[w].store((*mayExceed)[w], std::memory_order_relaxed);
        return true;
    }
    for (std::size_t w = 0; w < words_; ++w) marked_[w].store(0, std::memory_order_relaxed);
    for (Index p = 0; p + 1 < Index(springStart_.size()); ++p) {
        if (movedAt_[std::size_t(3 * p)] < movedSince) continue;
        for (Index e = springStart_[std::size_t(p)]; e < springStart_[std::size_t(p) + 1]; ++e)
            set<false>(marked_.get(), springsOf_[std::size_t(e)]);
    }
    return true;
}

int StretchLimit::apply(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                        Scalar h, State& state, ThreadPool* pool, const SpringBits* mayExceed) {
    prepare(model, maxStretch);
    const auto& springs = model.passSprings();
    const auto& start = model.passGroupStart();
    const Index blocks = model.passBlocks();
    const auto count = std::int64_t(springs.size());
    PassArgs args{check_.data(), springs.data(), state.x.data(), state.v.data(), model.masses().data(), pinned.data(),
                  1 + maxStretch, h, springStart_.data(), springsOf_.data(), marked_.get(), movedAt_.data(), stamps_,
                  std::numeric_limits<std::int64_t>::min() / 2};
    lastCall_ = stamps_;
    stamps_ += std::int64_t(passes) * count;  // what is left in movedAt_ is older than any stamp of a later call
    bool marking = mayExceed && markedFrom(mayExceed, 0);
    int corrections = 0;
    for (int pass = 0, last = 0; pass < passes; ++pass) {
        if (pass > 0) {
            args.checked = args.stamp, args.stamp += count;
            marking = std::int64_t(last) * kDense <= count && markedFrom(nullptr, args.checked);
        }
        // The blocks (on the pool's threads, which never changes a bit: they share no particle),
        // then the seam.
        std::atomic<int> inBlocks{0};
        if (pool && blocks > 1)
            pool->run(blocks, [&](int b0, int b1) {
                int n = 0;
                for (int b = b0; b < b1; ++b)
                    n += marking ? markRange<true>(args, start[b], start[b + 1]) : scanRange(args, start[b], start[b + 1]);
                inBlocks += n;
            });
        else
            inBlocks = marking ? markRange<false>(args, start[0], start[blocks]) : scanRange(args, start[0], start[blocks]);
        last = inBlocks + (marking ? markRange<false>(args, start[blocks], start[blocks + 1])
                                   : scanRange(args, start[blocks], start[blocks + 1]));
        corrections += last;
        if (last == 0) break;
    }
    return corrections;
}

}  // namespace cloth
