#pragma once
// A parallel step that a busy core slows down goes back to one thread for a while. When the
// scheduler takes a thread off its core (the other core busy, as in a game), the step's other
// thread waits at the next barrier for the rest of a time slice: milliseconds, against a substep's
// microseconds of work. The caller's waits over kMinLag are summed over a window of kWindow steps;
// as soon as they exceed its own work there by kAllowance, two threads ran slower than one would
// have (one thread does twice the work but waits for nobody), and the next kSoloSteps steps run on
// one thread (the same bits: the split never changes a result). Then two threads are tried again;
// if the first window after a spell lags too, the next spell is twice as long (up to
// kMaxSoloSteps), so a core that stays busy costs about one lagging step per spell, and a core
// that frees up gets its thread back within one spell. One late wait of a noisy machine, under
// kAllowance, sends nothing solo. Within a step, as soon as its waits exceed its work so far by
// kAllowance (partNow), its threads part at the end of the substep and the caller ends the step
// alone: a step of many substeps on a busy core would otherwise wait a time slice at many of them.

#include <algorithm>
#include <chrono>

namespace cloth {

class LagGuard {
public:
    using Duration = std::chrono::steady_clock::duration;
    static constexpr std::chrono::microseconds kMinLag{200};
    static constexpr std::chrono::milliseconds kAllowance{2};
    static constexpr int kWindow = 16, kSoloSteps = 64, kMaxSoloSteps = 64 << 8;

    // Whether this step runs on one thread; counts it against the spell.
    bool solo() {
        if (solo_ == 0) return false;
        if (--solo_ == 0) probing_ = true;
        return true;
    }
    // A wait of the caller's at a barrier of this step: only one over kMinLag counts.
    void waited(Duration d) {
        if (d > kMinLag) lagged_ += d;
    }
    // Within a parallel step, `elapsed` since it began: whether its threads part now (and from
    // then on in this step), its waits having exceeded its work so far by kAllowance.
    bool partNow(Duration elapsed) {
        parted_ = parted_ || lagged_ > elapsed - lagged_ + kAllowance;
        return parted_;
    }
    // After a parallel step of `total` (the caller's wall time, its waits included). A step whose
    // threads parted lagged.
    void stepEnded(Duration total) {
        work_ += total - lagged_, windowLag_ += lagged_, lagged_ = Duration::zero();
        const bool late = parted_ || windowLag_ > work_ + kAllowance;
        parted_ = false;
        if (!late && ++steps_ < kWindow) return;
        if (late) {
            spell_ = probing_ ? std::min(2 * spell_, kMaxSoloSteps) : kSoloSteps;
            solo_ = spell_;
            ++spells_;
        }
        probing_ = false, steps_ = 0, work_ = windowLag_ = Duration::zero();
    }
    long spells() const { return spells_; }
    int spellLength() const { return spell_; }

private:
    Duration lagged_{}, work_{}, windowLag_{};
    int steps_ = 0;          // parallel steps in this window
    int solo_ = 0;           // steps still to run on one thread
    int spell_ = 0;          // the last spell's length
    bool probing_ = false;   // this window is the first after a spell
    bool parted_ = false;    // this step's threads parted
    long spells_ = 0;
};

}  // namespace cloth
