#pragma once
// Part 2 of the study (extreme.csv): the demo's flag and the stiff scene's flag on a carrier
// driven through extreme motions (extreme_cases.h), per configuration (configurations.h), judged
// against the flag's fine-step reference (extreme_runs.h): stable or not, stretch, the kinetic
// energy in the carrier's frame (mean, last second, per 0.5 s window, and at the scale of
// patches), and the trajectory error over 0.25 s horizons restarted from the reference's states.
// extreme_cases.csv: per case, the largest speed and acceleration its carrier gives the flag's
// pinned column; the study stops before any work when a case moves no pin and has no wind (it
// would test nothing).

#include <string>
#include <vector>

#include "configurations.h"
#include "engine/scene.h"
#include "extreme_cases.h"
#include "study_options.h"
#include "work_items.h"

namespace study {

// The guard on every extreme case: its carrier moves the flag's pins, or it has wind. Writes each
// case's largest pin speed and acceleration to `csv` (unless empty); false, with the reason on
// stderr, when a case drives nothing.
bool extremeCasesDriveTheFlag(const engine::SceneConfig& demo, const std::string& csv);

// Writes OUT/extreme.csv: each case x size x configuration a row, the rows of the work items this
// shard holds; returns the whole run's number of rows.
long runExtremes(const StudyOptions& o, const engine::SceneConfig& demo, const engine::SceneConfig& stiff,
                 const std::vector<Extreme>& cases, const std::vector<int>& sizes,
                 const std::vector<Configuration>& configs, WorkItems& work);

}  // namespace study
