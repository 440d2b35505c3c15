#pragma once
// The constraints' first tests on the stencil (stencil_cloth.h), in float SIMD: which springs could
// be over the stretch limit and which particles beyond their tether (ConstraintSet::apply's
// hints). A spring or particle is listed when its squared length (to its anchor) in float exceeds
// (1 - kMargin) times the square it may reach; float's rounding of a squared length is some 1e-7
// of it, so one left out is within its bound in double too, and the constraints give the same
// bits as checking every spring and particle.

#include <cstdint>
#include <vector>

#include "cloth/constraints.h"
#include "small_steps/stencil_cloth.h"

namespace cloth {

class ConstraintCheck {
public:
    static constexpr double kMargin = 1e-4;

    // What `set`'s constraints for `model` and `pins` need check in positions `x` (on the stencil,
    // relative to any origin): prepare, test every slot, then collect.
    const ConstraintHints& hints(const StencilCloth& cloth, const Model& model, const std::vector<Pin>& pins,
                                 ConstraintSet& set, const Vec3Field& x);

    // The tables for `set`'s constraints for `model` and `pins` (kept while they stay the same).
    void prepare(const StencilCloth& cloth, const Model& model, const std::vector<Pin>& pins, ConstraintSet& set);
    // The tests of the springs at slots [begin, end) and of those particles (threads may test
    // disjoint ranges at once; x must not change meanwhile).
    void test(const StencilCloth& cloth, const Vec3Field& x, int begin, int end);
    // The hints from every slot's test.
    const ConstraintHints& collect(const StencilCloth& cloth);

private:
    void buildSprings(const StencilCloth& cloth, const Model& model, const StretchLimit& limit);
    void buildTethers(const StencilCloth& cloth, const Tethers& tethers, Scalar maxStretch);

    ConstraintHints hints_;
    // The stretch limit's: per family, per slot, the squared length over which the spring is
    // listed (+inf at a slot with no spring) and its pass index.
    std::uint64_t springsFor_ = 0;  // the model
    Scalar stretchFor_ = -1;        // and the limit they were built for
    std::vector<PaddedField> springOver_;
    std::vector<std::vector<Index>> passIndex_;
    // The tethers': per particle, its anchor (itself when untethered), the squared distance over
    // which it is listed (+inf when untethered) and its index among the tethered.
    std::uint64_t tethersFor_ = 0;
    long tethersVersion_ = -1;
    Scalar tetherFor_ = -1;
    std::vector<int> anchor_;
    PaddedField tetherOver_;
    std::vector<Index> tetherIndex_;
    bool springs_ = false, tethers_ = false;  // which the constraints have
    // Per family, then the particles: per slot, whether the test listed it.
    std::vector<std::vector<std::uint8_t>> over_;
};

}  // namespace cloth
