#pragma once
// The cloth's constraints: corrections after a solver's step, set beside the solver (a scene's
// flag.constraints, cloth_run's --constraints), whichever solver steps the cloth. Two kinds, in
// this order: tethers, then the stretch limit.
//
// The stretch limit, in the manner of Provot 1995 ("Deformation constraints in a
// mass-spring model to describe rigid cloth behavior"): after a step, every spring stretched
// beyond (1 + maxStretch) times its rest length has its ends pulled together to that length
// (split by inverse mass; pinned ends do not move), for a few Gauss-Seidel passes in the order of
// Model::passSprings(): in spring order within bands of particles, which share no particle and so
// run on the pool's threads with the same bits for any thread count, then the springs between
// the bands. The velocity of each moved particle changes by its correction / h, so the
// constraint also removes the stretching velocity.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "cloth/constraint_settings.h"
#include "cloth/model.h"
#include "cloth/system.h"
#include "cloth/thread_pool.h"

namespace cloth {

// The springs in Model::passSprings()'s order as bits: spring k is bit k % 64 of word k / 64.
using SpringBits = std::vector<std::uint64_t>;
inline void addSpring(SpringBits& bits, Index k) { bits[std::size_t(k) / 64] |= std::uint64_t(1) << (k % 64); }

// The stretch limit, with its tables (per spring: where its ends' coordinates start and the
// squared length it may reach; per particle: its springs) kept while the model and the limit stay
// the same.
//
// A pass checks only the springs with an end that moved since the spring was last checked: the
// others would find what their last check found, from the same positions, nothing to correct
// (the same bits as checking every spring in every pass). It finds them one of two ways, whichever
// costs less for the moves of the pass before: a scan of every spring against when its ends last
// moved, or, when few moved, bits marking the springs of the particles that moved (a correction
// marks its ends' springs later in the pass). The first pass checks every spring, or only those a
// caller's cheaper test could not clear (`mayExceed`).
class StretchLimit {
public:
    // Returns the number of corrections applied. `pinned[i] != 0` marks particles that must not
    // move. `mayExceed` (optional): every spring not in it is within its limit in `state`.
    int apply(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes, Scalar h,
              State& state, ThreadPool* pool = nullptr, const SpringBits* mayExceed = nullptr);
    // The tables for `model` and `maxStretch` (apply builds them too).
    void prepare(const Model& model, Scalar maxStretch);
    // Adds the springs of `particle` to `bits` (the prepared model's).
    void addSpringsOf(Index particle, SpringBits& bits) const;
    // Calls fn(particle) for each particle the last apply moved.
    template <class Fn>
    void forEachMoved(Fn fn) const {
        for (std::size_t c = 0; c < movedAt_.size(); c += 3)
            if (movedAt_[c] >= lastCall_) fn(Index(c / 3));
    }
    // The squared length at or under which spring k (in pass order) is left alone.
    Scalar within(Index k) const { return check_[std::size_t(k)].within; }

    struct Check {
        Index xi = 0, xj = 0;
        Scalar within = 0;
    };

private:
    bool markedFrom(const SpringBits* mayExceed, std::int64_t movedSince);

    std::uint64_t model_ = 0;
    Scalar maxStretch_ = -1;
    std::vector<Check> check_;
    std::vector<Index> springStart_, springsOf_;  // per particle, its springs' pass indices, increasing
    // When each particle last moved, as its pass's stamp + the spring that moved it (indexed by its
    // first coordinate, as a Check's xi). Each pass's stamp is the last one's + springs, across
    // calls (stamps_: the next call's first), so that a move of an earlier call reads as older
    // than any check of this one and the table is never cleared.
    std::vector<std::int64_t> movedAt_;
    std::int64_t stamps_ = 0;
    std::int64_t lastCall_ = 0;  // the last apply's first stamp
    // The springs a marking pass checks (atomic: the blocks' threads mark the seam's).
    std::unique_ptr<std::atomic<std::uint64_t>[]> marked_;
    std::size_t words_ = 0;
};

// Long-range attachments (Kim, Chentanez & Mueller 2012, "Long range attachments - a method to
// simulate inextensible clothing in computer games"), the stretch bound of game engines' cloth
// (NvCloth's tethers, Jolt's long-range attachments). Each free particle's anchor is the pinned
// particle nearest to it at rest; after a step, a particle farther from its anchor than
// (1 + maxStretch) times their rest distance is moved straight back onto that sphere, its
// velocity changed by its correction / h. One pass, each particle on its own: no particle waits
// on another, so it costs a pass over the particles whatever the stretch, where the stretch
// limit's Gauss-Seidel chains need many passes to carry a correction across the cloth. It bounds
// the distance to the pole, not a single spring's stretch.
class Tethers {
public:
    // Anchors are found again (a pass over particles x pins) only when the pinned particles change.
    // Returns the number of particles moved.
    // The particles are split among `pool`'s threads when given (each on its own: the same bits).
    // `mayExceed` (optional): the tethered particles (indices into tethered(), increasing) that may
    // be beyond their bound; every other one is within it in `state`.
    int apply(const Model& model, const std::vector<Pin>& pins, Scalar maxStretch, Scalar h, State& state,
              ThreadPool* pool = nullptr, const std::vector<Index>* mayExceed = nullptr);
    // The anchors for `pins` (apply finds them too).
    void prepare(const Model& model, const std::vector<Pin>& pins);
    // Per tethered particle, in apply's order: the particle, its anchor and their rest distance;
    // version() changes when they do.
    const std::vector<Index>& tethered() const { return free_; }
    const std::vector<Index>& anchors() const { return anchor_; }
    const std::vector<Scalar>& restDistances() const { return rest_; }
    long version() const { return version_; }
    // Calls fn(particle) for each particle the last apply moved.
    template <class Fn>
    void forEachMoved(Fn fn) const {
        for (std::size_t k = 0; k < moved_.size(); ++k)
            if (moved_[k]) fn(free_[k]);
    }

private:
    std::vector<Index> pinned_;  // the pins' particles the anchors were found for
    std::vector<Index> current_;  // apply()'s scratch: this call's pins' particles
    Index particles_ = -1;
    std::vector<Index> free_, anchor_;
    std::vector<Scalar> rest_;
    std::vector<std::uint8_t> moved_;  // per free particle: the last apply moved it
    long version_ = 0;
};

// What a caller's cheaper tests found (ConstraintSet::apply), in the state handed in: every
// tethered particle not in `tethers` (indices into Tethers::tethered(), increasing) is within its
// bound, every spring not in `springs` within the stretch limit.
struct ConstraintHints {
    std::vector<Index> tethers;
    SpringBits springs;
    bool empty() const {
        return tethers.empty() && std::all_of(springs.begin(), springs.end(), [](std::uint64_t w) { return w == 0; });
    }
};

// The cloth's constraints with their workspaces: what a solver applies after each step.
class ConstraintSet {
public:
    void set(const Constraints& c) { settings_ = c; }
    const Constraints& settings() const { return settings_; }
    bool any() const { return settings_.any(); }
    // Tethers, then the stretch limit, on `state` after a step of length h (the pins' particles
    // stay put). Returns the number of corrections (particles the tethers moved, and the stretch
    // limit's). `hints` (optional): what need be checked (the springs of particles the tethers
    // move are added to its springs).
    int apply(const Model& model, const std::vector<Pin>& pins, Scalar h, State& state, ThreadPool* pool,
              const ConstraintHints* hints = nullptr);
    // The stretch limit's tables for `model` and the tethers' for `pins` (for a caller's hints).
    const StretchLimit& stretchLimit(const Model& model) {
        stretch_.prepare(model, settings_.stretchLimit);
        return stretch_;
    }
    const Tethers& tethers(const Model& model, const std::vector<Pin>& pins) {
        tethers_.prepare(model, pins);
        return tethers_;
    }
    // Calls fn(particle) for each particle the last apply moved (some twice).
    template <class Fn>
    void forEachMoved(Fn fn) const {
        if (settings_.tether > 0) tethers_.forEachMoved(fn);
        if (settings_.stretchLimit > 0) stretch_.forEachMoved(fn);
    }

private:
    Constraints settings_;
    Tethers tethers_;
    StretchLimit stretch_;
    std::vector<std::uint8_t> pinned_;
    SpringBits mayExceed_;  // the caller's, with the tethers' moves
};

}  // namespace cloth
