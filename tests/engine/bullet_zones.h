#pragma once
// Bullet's profile zones as a tick opens them, three levels deep, for the profiler's tests.

#include "engine/profile/profiler.h"

inline void enterAndLeaveBulletZones(engine::Profiler& p) {
    p.enterZone("internalSingleStepSimulation");
    p.enterZone("stepSimulation");
    p.enterZone("deeper");
    p.leaveZone();
    p.leaveZone();
    p.leaveZone();
}
