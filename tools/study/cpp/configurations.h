#pragma once
// The front's configurations (front.h): what a user could pick for a flag, each a solver with
// its constraints at a physics rate, or the flag's fine-step reference; a table with named fields.
// A configuration runs on both flags (the demo's soft flag, the stiff scene's) unless it says
// otherwise; on each it has that flag's model: its springs, mass and air, and its constraints
// unless the configuration drops them.

#include <optional>
#include <string>
#include <vector>

#include "engine/scene/scene.h"
#include "study_options.h"

namespace study {

enum class FlagKind { Demo, Stiff };
const char* flagName(FlagKind flag);  // "demo", "stiff"

struct Configuration {
    std::string name = {};
    std::string solver = {};  // a solver spec ("" for a reference, or the shipped scene's)
    // The cloth's constraints, "key=value,..."; unset: the flag's own (its model); "": none.
    std::optional<std::string> constraints = {};
    int substeps = 1;         // solver steps per physics tick (the air and collisions at each)
    int implicitAir = -1;     // -1: as the flag's scene says, else 0 / 1
    int hz = 240;             // physics rate
    int referenceFactor = 0;  // > 0: the flag's fine-step reference, its substeps times this
    bool springsOnly = false; // a reference: the springs alone, without the flag's constraints
    bool paced = true;        // a reference: substeps also paced by the pins' moves (extreme_runs.h)
    bool shipped = false;     // the flag's scene as it ships: its solver, constraints, substeps, rate
    std::vector<FlagKind> flags = {FlagKind::Demo, FlagKind::Stiff};
    int maxSide = 0;          // > 0: not above this side (its cost there is many frames per frame)
    // Only with --contact (configurations that set any): contact after every this many substeps
    // (cloth::ContactSettings::substepStride; 0: once after each tick), with a move > 0 only once
    // the fastest particle has also moved that far relative to the pole (m;
    // ContactSettings::strideMove), and self pairs bounded by half-spaces (SelfBounds::HalfSpaces).
    int contactStride = 1;
    double contactStrideMove = 0;
    bool halfSpaces = false;
    // A peer that steps in another process: its cost is the cloth's own profile (its step as it
    // timed it) and the row's timing says whose clock ("warp_cpu"); null: the tick's wall time.
    const char* timing = nullptr;

    bool runsOn(FlagKind flag, int side) const;
};

// The study's configurations (--quick: a few), then --add-configs'. An error (for a bad
// --add-configs item) empties the list and sets *error.
std::vector<Configuration> configurations(const StudyOptions& o, std::string* error);

}  // namespace study
