#include "engine/clock/tick_clock.h"

#include <cmath>

namespace engine {

TickClock::TickClock(double physicsHz, double fps, int maxTicksPerFrame, bool lockstep)
    : physicsHz_(physicsHz), fps_(fps), tickDt_(1.0 / physicsHz), maxTicksPerFrame_(maxTicksPerFrame),
      lockstep_(lockstep) {}

void TickClock::startWall(Clock::time_point now) {
    lastWall_ = now;
    accumulator_ = 0;
}

long long TickClock::ticksDue(int frame, Clock::time_point now) {
    return lockstep_ ? lockstepTicks(frame) : wallTicks(now);
}

void TickClock::setPhysicsHz(double physicsHz, int frame) {
    timeBase_ = simTime();
    ticksBase_ = ticks_;
    frameBase_ = frame;
    physicsHz_ = physicsHz;
    tickDt_ = 1.0 / physicsHz;
}

// The schedule's ticks by the end of this frame, less those already run.
long long TickClock::lockstepTicks(int frame) const {
    const long long target =
        ticksBase_ + static_cast<long long>(std::floor((frame - frameBase_ + 1) * physicsHz_ / fps_ + 1e-9));
    return target - ticks_;
}

// The whole ticks in the wall time since the last frame plus the remainder carried over, capped.
long long TickClock::wallTicks(Clock::time_point now) {
    accumulator_ += std::chrono::duration<double>(now - lastWall_).count();
    lastWall_ = now;
    long long due = static_cast<long long>(accumulator_ / tickDt_);
    if (due > maxTicksPerFrame_) {
        due = maxTicksPerFrame_;
        accumulator_ = 0;  // drop the backlog instead of spiralling
    } else {
        accumulator_ -= due * tickDt_;
    }
    return due;
}

}  // namespace engine
