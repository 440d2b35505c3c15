#include "small_steps/constraint_check.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

#include "simd.h"

namespace cloth {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// over[p] = 1 where family d's spring at slot p is longer than listedOver[p] allows (or not a
// number), for p in [0, n).
CLOTH_SIMD_CLONES void springsOver(const float* x, const float* y, const float* z, int d, const float* listedOver, int n,
                                   std::uint8_t* over) {
    CLOTH_IVDEP
    for (int p = 0; p < n; ++p) {
        const float dx = x[p + d] - x[p], dy = y[p + d] - y[p], dz = z[p + d] - z[p];
        over[p] = !(dx * dx + dy * dy + dz * dz <= listedOver[p]);  // a NaN too
    }
}

// over[p] = 1 where particle p is farther from anchor[p] than listedOver[p] allows (or not a
// number), for p in [begin, end).
CLOTH_SIMD_CLONES void particlesOver(const float* x, const float* y, const float* z, const int* anchor,
                                     const float* listedOver, int begin, int end, std::uint8_t* over) {
    CLOTH_IVDEP
    for (int p = begin; p < end; ++p) {
        const int a = anchor[p];
        const float dx = x[p] - x[a], dy = y[p] - y[a], dz = z[p] - z[a];
        over[p] = !(dx * dx + dy * dy + dz * dz <= listedOver[p]);
    }
}

// over_'s slots per family: the cloth's, rounded up to eight (the rest stay 0).
std::size_t slots(const StencilCloth& cloth) { return (std::size_t(cloth.n) + 7) / 8 * 8; }

// fn(slot) for each slot of over[0, n) that is set, in order (n a multiple of eight; mostly none:
// eight slots at a time).
template <class Fn>
void forEachOver(const std::uint8_t* over, std::size_t n, Fn fn) {
    for (std::size_t p = 0; p < n; p += 8) {
        std::uint64_t eight;
        std::memcpy(&eight, over + p, 8);
        for (; eight != 0; eight &= eight - 1) fn(p + std::size_t(std::countr_zero(eight)) / 8);  // each byte 0 or 1
    }
}

// The square `within` may reach, listed from (1 - kMargin) of it.
float listedFrom(Scalar within) { return float(within * (1 - ConstraintCheck::kMargin)); }

}  // namespace

const ConstraintHints& ConstraintCheck::hints(const StencilCloth& cloth, const Model& model, const std::vector<Pin>& pins,
                                              ConstraintSet& set, const Vec3Field& x) {
    prepare(cloth, model, pins, set);
    test(cloth, x, 0, cloth.n);
    return collect(cloth);
}

void ConstraintCheck::prepare(const StencilCloth& cloth, const Model& model, const std::vector<Pin>& pins,
                              ConstraintSet& set) {
    const Constraints& c = set.settings();
    springs_ = c.stretchLimit > 0, tethers_ = c.tether > 0;
    if (springs_ && (springsFor_ != cloth.modelId || stretchFor_ != c.stretchLimit))
        buildSprings(cloth, model, set.stretchLimit(model)), springsFor_ = cloth.modelId, stretchFor_ = c.stretchLimit;
    if (tethers_) {
        const Tethers& tethers = set.tethers(model, pins);
        if (tethersFor_ != cloth.modelId || tethersVersion_ != tethers.version() || tetherFor_ != c.tether)
            buildTethers(cloth, tethers, c.tether), tethersFor_ = cloth.modelId, tethersVersion_ = tethers.version(),
                                                    tetherFor_ = c.tether;
    }
    over_.resize(cloth.offsets.size() + 1);
    for (auto& o : over_) o.resize(slots(cloth));
}

void ConstraintCheck::test(const StencilCloth& cloth, const Vec3Field& x, int begin, int end) {
    const float *px = x.x.at() + begin, *py = x.y.at() + begin, *pz = x.z.at() + begin;
    const std::size_t families = cloth.offsets.size();
    for (std::size_t f = 0; springs_ && f < families; ++f)
        springsOver(px, py, pz, cloth.offsets[f], springOver_[f].at() + begin, end - begin, over_[f].data() + begin);
    if (tethers_) particlesOver(x.x.at(), x.y.at(), x.z.at(), anchor_.data(), tetherOver_.at(), begin, end, over_[families].data());
}

const ConstraintHints& ConstraintCheck::collect(const StencilCloth& cloth) {
    const std::size_t families = cloth.offsets.size();
    if (springs_) {
        std::fill(hints_.springs.begin(), hints_.springs.end(), 0);
        for (std::size_t f = 0; f < families; ++f)
            forEachOver(over_[f].data(), over_[f].size(), [&](std::size_t p) {
                const Index k = passIndex_[f][p];
                if (k >= 0) addSpring(hints_.springs, k);
            });
    }
    hints_.tethers.clear();
    if (tethers_)
        forEachOver(over_[families].data(), over_[families].size(), [&](std::size_t p) {
            if (tetherIndex_[p] >= 0) hints_.tethers.push_back(tetherIndex_[p]);
        });
    return hints_;
}

void ConstraintCheck::buildSprings(const StencilCloth& cloth, const Model& model, const StretchLimit& limit) {
    const std::size_t families = cloth.offsets.size();
    springOver_.assign(families, {});
    passIndex_.assign(families, std::vector<Index>(slots(cloth), -1));
    for (PaddedField& f : springOver_) {
        f.assign(cloth.n, cloth.pad);
        std::fill(f.storage.begin(), f.storage.end(), kInf);
    }
    const auto& springs = model.passSprings();
    for (Index k = 0; k < Index(springs.size()); ++k) {
        const PassSpring& s = springs[std::size_t(k)];
        const int lo = int(std::min(s.i, s.j)), d = int(std::max(s.i, s.j)) - lo;
        const auto f = std::size_t(std::lower_bound(cloth.offsets.begin(), cloth.offsets.end(), d) - cloth.offsets.begin());
        springOver_[f].at()[lo] = listedFrom(limit.within(k));
        passIndex_[f][std::size_t(lo)] = k;
    }
    hints_.springs.assign((springs.size() + 63) / 64, 0);
}

void ConstraintCheck::buildTethers(const StencilCloth& cloth, const Tethers& tethers, Scalar maxStretch) {
    anchor_.resize(slots(cloth));
    for (int p = 0; p < int(anchor_.size()); ++p) anchor_[std::size_t(p)] = std::min(p, cloth.n - 1);
    tetherOver_.assign(int(slots(cloth)), cloth.pad);
    std::fill(tetherOver_.storage.begin(), tetherOver_.storage.end(), kInf);
    tetherIndex_.assign(slots(cloth), -1);
    for (std::size_t k = 0; k < tethers.tethered().size(); ++k) {
        const auto p = std::size_t(tethers.tethered()[k]);
        const Scalar limit = (1 + maxStretch) * tethers.restDistances()[k];
        anchor_[p] = int(tethers.anchors()[k]), tetherOver_.at()[p] = listedFrom(limit * limit), tetherIndex_[p] = Index(k);
    }
}

}  // namespace cloth
