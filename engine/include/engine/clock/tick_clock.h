#pragma once
// The fixed-step clock: how many physics ticks each frame runs, and the simulated time.
//
// In lockstep (headless runs, replays, runs that record their input) frame k ends with exactly
// floor((k + 1) * physics_hz / fps) ticks done, whatever the wall clock did, so the same scene
// and script give the same frames. Otherwise an accumulator follows the wall clock: a frame runs
// the whole ticks that elapsed since the previous frame and keeps the remainder; more than
// max_ticks_per_frame are capped and the backlog dropped, so a slow frame cannot spiral.

#include <chrono>

namespace engine {

class TickClock {
public:
    using Clock = std::chrono::steady_clock;

    TickClock(double physicsHz, double fps, int maxTicksPerFrame, bool lockstep);

    // Wall-clock mode counts the time from here (the first frame's ticks are those since now).
    void startWall(Clock::time_point now = Clock::now());
    // The ticks frame `frame` (0-based, called once per frame in order) runs. `now` is read only
    // in wall-clock mode.
    long long ticksDue(int frame, Clock::time_point now = Clock::now());
    void countTick() { ++ticks_; }  // one tick has run
    // From frame `frame` on, ticks of 1/physicsHz: the schedule restarts at the ticks and the time
    // reached, so the frames before keep theirs.
    void setPhysicsHz(double physicsHz, int frame);
    // From frame `frame` on, the schedule counts from the ticks reached (after single steps).
    void restartSchedule(int frame) { setPhysicsHz(physicsHz_, frame); }

    long long ticks() const { return ticks_; }
    double tickDt() const { return tickDt_; }
    double physicsHz() const { return physicsHz_; }
    double simTime() const { return timeBase_ + (ticks_ - ticksBase_) * tickDt_; }
    bool lockstep() const { return lockstep_; }

private:
    long long lockstepTicks(int frame) const;
    long long wallTicks(Clock::time_point now);

    double physicsHz_, fps_, tickDt_;
    int maxTicksPerFrame_;
    bool lockstep_;
    long long ticks_ = 0;
    long long ticksBase_ = 0;  // ticks and time when the rate last changed, and the frame it changed at
    double timeBase_ = 0;
    int frameBase_ = 0;
    double accumulator_ = 0;  // wall seconds not yet run as ticks
    Clock::time_point lastWall_ = Clock::now();
};

}  // namespace engine
