#pragma once
// The configurations of the extreme cases (front.h): each a solver with its constraints on one of
// the two flags (the demo's, the stiff scene's) at a physics rate, or that flag's fine-step
// reference; a table with named fields.

#include <string>
#include <vector>

#include "engine/scene.h"
#include "study_options.h"

namespace study {

struct Configuration {
    std::string name = {};
    std::string solver = {};       // a solver spec ("" for a reference)
    std::string constraints = {};  // the cloth's constraints, "key=value,..." ("" for none)
    int substeps = 1;         // solver steps per physics tick
    int implicitAir = -1;     // -1: as the scene says, else 0 / 1
    bool stiff = false;       // the stiff scene's flag, else the demo's
    int hz = 0;               // physics rate (0: the scene's)
    int referenceFactor = 0;  // > 0: the flag's fine-step reference, its substeps times this
};

// The study's configurations (--quick: the demo's flag's few), then --stiff-configs'; the demo's
// scene (--extreme-scene) gives demo_default, the stiff scene stiff_default. An error (for a bad
// --stiff-configs item) empties the list and sets *error.
std::vector<Configuration> configurations(const StudyOptions& o, const engine::SceneConfig& demo,
                                          const engine::SceneConfig& stiff, std::string* error);

}  // namespace study
