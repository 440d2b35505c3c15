#pragma once
// The study's flags and pole motions as JSON for NVIDIA Newton's harness
// (tools/study/flagstudy/nvidia_newton_study.py, which has no link to this code): every part-1 configuration at
// k = 1e4, h = 1/240 s, and every extreme case and size (--quick: the teleport).

#include <string>
#include <vector>

#include "engine/scene/scene.h"
#include "extreme_cases.h"
#include "solve_error.h"

namespace study {

// Writes the JSON files into o.exportDir; returns the exit code.
int exportForNvidiaNewton(const StudyOptions& o, const std::vector<SolveErrorConfig>& configs,
                          const engine::SceneConfig& demo, const std::vector<Extreme>& cases,
                          const std::vector<int>& sizes);

}  // namespace study
