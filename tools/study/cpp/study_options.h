#pragma once
// cloth_study's command line: the options of a run, read and checked before any work starts.

#include <string>
#include <vector>

namespace study {

struct StudyOptions {
    bool quick = false, frontOnly = false, scan = true, front = true, parallel = false, trajectories = true,
         references = true;
    int shard = 1, shards = 1;
    std::vector<int> frontSizes;    // default: 33 and 65 (--quick: 33)
    int trajectoryMaxSide = 33;     // traj_error up to this side (restarted runs against the reference)
    std::vector<int> sizeOverride;  // part 1's sizes instead of its list
    std::string out = "out/study", exportDir, demoScenePath = "flag_vehicle";
    std::vector<std::string> sceneFilter, solverSpecs, configFilter, pathFilter, flagFilter, extraConfigs;
    std::vector<double> teleports;  // more teleport paths, by the jump in m (--teleports)
    std::string cacheDir = FLAGSIM_STUDY_CACHE_DIR;  // the references' cache (--cache-dir; --no-cache: "")
    bool progressLines = false;  // a line per row even on a terminal (--progress-lines)
    bool contact = false;        // both flags, their references too, with contact (--contact)
    bool nvidiaNewton = false;   // NVIDIA Newton's solvers in the front too (--nvidia-newton)
};

// Reads the command line into `o`. Returns -1 to go on, else the exit code: 0 after --help, 2 for
// a bad option (with the reason and the usage on stderr).
int parseOptions(int argc, char** argv, StudyOptions& o);

// Prints "cloth_study: why" and the usage on stderr; returns 2.
int usageError(const std::string& why);

// The non-empty parts of `text` between `sep`s.
std::vector<std::string> split(const std::string& text, char sep);

}  // namespace study
