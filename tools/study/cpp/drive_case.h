#pragma once
// The demo's drive as a path of the study: the pole's path under the demo's drive script
// (assets/scripts/drive.json), from the demo's own vehicle on Bullet, with the air; the flag
// flutters to its end. Its carrier is the pole's frame (the chassis frame moved to the pole's
// base), so the flag rides it as in the other cases (extremeMount).

#include "engine/scene/scene.h"
#include "extreme_cases.h"

namespace study {

// The drive, `demo`'s vehicle driven by its script for its duration. Bullet ticks at 960 Hz (as
// part 1's vehicle_path records it); between ticks the pole's pose is interpolated.
Extreme driveCase(const engine::SceneConfig& demo);

}  // namespace study
