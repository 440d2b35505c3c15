#pragma once
// The front (front.csv): for each flag (the demo's, the stiff scene's), path (the demo's drive,
// drive_case.h, and the extreme cases, extreme_cases.h) and size, every configuration
// (configurations.h) judged against that flag's fine-step reference (extreme_runs.h): its cost
// (ms per tick, and per 60 Hz frame), its trajectory error over 0.25 s horizons restarted from
// the reference's states, its stretch and flutter energy against the reference's, stable or not,
// and the bounds it misses (bounds.h).
// extreme_cases.csv: per path, the largest speed and acceleration its carrier gives the flag's
// pinned column; the study stops before any work when a path moves no pin and has no wind (it
// would test nothing).

#include <string>
#include <vector>

#include "configurations.h"
#include "engine/scene/scene.h"
#include "extreme_cases.h"
#include "extreme_runs.h"
#include "progress.h"
#include "reference_cache.h"
#include "study_options.h"
#include "work_items.h"

namespace study {

// The two flags' scenes.
struct Flags {
    engine::SceneConfig demo, stiff;
    const engine::SceneConfig& of(FlagKind flag) const { return flag == FlagKind::Demo ? demo : stiff; }
};

// The guard on every path: its carrier moves the flag's pins, or it has wind. Writes each path's
// largest pin speed and acceleration to `csv` (unless empty); false, with the reason on stderr,
// when a path drives nothing.
bool pathsDriveTheFlag(const engine::SceneConfig& demo, const std::vector<Extreme>& paths, const std::string& csv);

// What the front runs: its options, the two flags' scenes, the flags, paths, sizes and
// configurations.
struct FrontPlan {
    const StudyOptions& options;
    const Flags& flags;
    const std::vector<FlagKind>& flagKinds;
    const std::vector<Extreme>& paths;
    const std::vector<int>& sizes;
    const std::vector<Configuration>& configs;
};

// Writes OUT/front.csv: each path x size x flag x configuration a row, the rows of the work items
// this shard holds, each told to `progress` as it is done; each group's reference from `cache`.
// Returns the whole run's number of rows.
long runFront(const FrontPlan& plan, WorkItems& work, ReferenceCache& cache, Progress& progress);
// The rows of the front that runFront would run for `work`'s shard, starting where it stands.
long frontRows(const FrontPlan& plan, WorkItems work);

}  // namespace study
