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

#include <cstdint>
#include <vector>

#include "cloth/constraint_settings.h"
#include "cloth/model.h"
#include "cloth/system.h"
#include "cloth/thread_pool.h"

namespace cloth {

// The stretch limit, with its check table (per spring: where its ends' coordinates start and the
// squared length it may reach) kept while the model and the limit stay the same.
class StretchLimit {
public:
    // Returns the number of corrections applied. `pinned[i] != 0` marks particles that must not move.
    int apply(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes, Scalar h,
              State& state, ThreadPool* pool = nullptr);

    struct Check {
        Index xi = 0, xj = 0;
        Scalar within = 0;
    };

private:
    std::uint64_t model_ = 0;
    Scalar maxStretch_ = -1;
    std::vector<Check> check_;
    // When each particle last moved, as its pass's stamp + the spring that moved it (indexed by its
    // first coordinate, as a Check's xi): a pass after the first checks only the springs with an
    // end that moved since the last pass checked them. The others would find what that check
    // found, from the same positions: nothing to correct (the same bits). Each pass's stamp is the
    // last one's + springs, across calls (stamps_: the next call's first), so that a move of an
    // earlier call reads as older than any check of this one and the table is never cleared.
    std::vector<std::int64_t> movedAt_;
    std::int64_t stamps_ = 0;
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
    int apply(const Model& model, const std::vector<Pin>& pins, Scalar maxStretch, Scalar h, State& state,
              ThreadPool* pool = nullptr);

private:
    std::vector<Index> pinned_;  // the pins' particles the anchors were found for
    std::vector<Index> current_;  // apply()'s scratch: this call's pins' particles
    Index particles_ = -1;
    std::vector<Index> free_, anchor_;
    std::vector<Scalar> rest_;
};

// The cloth's constraints with their workspaces: what a solver applies after each step.
class ConstraintSet {
public:
    void set(const Constraints& c) { settings_ = c; }
    const Constraints& settings() const { return settings_; }
    bool any() const { return settings_.any(); }
    // Tethers, then the stretch limit, on `state` after a step of length h (the pins' particles
    // stay put). Returns the number of corrections (particles the tethers moved, and the stretch
    // limit's).
    int apply(const Model& model, const std::vector<Pin>& pins, Scalar h, State& state, ThreadPool* pool);

private:
    Constraints settings_;
    Tethers tethers_;
    StretchLimit stretch_;
    std::vector<std::uint8_t> pinned_;
};

}  // namespace cloth
