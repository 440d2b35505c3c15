// cloth_study: error against run time, and stability on stiff and extreme cases.
//
//   cloth_study [--quick] [--out DIR]      (tools/run study [--quick] runs it and plots)
//   cloth_study --help                     (every option: subsets of scenes, sizes and solvers)
//
// Part 1 (solve_error.h, error_vs_runtime.csv): every solver on the same cloth against the
// converged backward Euler step. Part 2 (front.h, extreme.csv): the demo's flag and the stiff
// scene's flag in extreme cases, per configuration (configurations.h), against each flag's
// fine-step reference. --export-nvidia-newton writes the same flags and pole motions for NVIDIA
// Newton's harness instead (nvidia_newton_export.h).

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "configurations.h"
#include "extreme_cases.h"
#include "front.h"
#include "nvidia_newton_export.h"
#include "solve_error.h"
#include "study_options.h"

using namespace study;

namespace {

using Clock = std::chrono::steady_clock;

// shard.json: which part of the work this run holds and how many rows the whole run has, so that
// merge_shards.py can tell a complete set of shards from an incomplete one.
void writeShardInfo(const StudyOptions& o, long configRows, long extremeRows) {
    std::ofstream f(o.out + "/shard.json");
    f << "{\"shard\": " << o.shard << ", \"of\": " << o.shards << ", \"rows\": {\"error_vs_runtime.csv\": " << configRows
      << ", \"extreme.csv\": " << extremeRows << "}}\n";
}

// Keeps the items of `all` named in `names` (none: all), in that order; false with the first
// unknown name in `unknown`.
template <class Item>
bool chooseByName(std::vector<Item>& all, const std::vector<std::string>& names, std::string& unknown) {
    if (names.empty()) return true;
    std::vector<Item> chosen;
    for (const std::string& name : names) {
        const auto it = std::find_if(all.begin(), all.end(), [&](const Item& x) { return x.name == name; });
        if (it == all.end()) return unknown = name, false;
        chosen.push_back(*it);
    }
    all = std::move(chosen);
    return true;
}

// A shipped scene by name or path, or the reason it cannot be read.
bool loadSceneNamed(const std::string& name, engine::SceneConfig& out, std::string& why) {
    try {
        out = engine::loadScene(engine::resolveScenePath(name, FLAGSIM_ASSETS_DIR));
        return true;
    } catch (const std::exception& e) {
        why = e.what();
        return false;
    }
}

// What the extreme cases run: the two flags' scenes, the configurations, the cases and sizes.
struct ExtremeWork {
    engine::SceneConfig demo, stiff;
    std::vector<Configuration> configs;
    std::vector<Extreme> cases = extremes();
    std::vector<int> sizes;
};

// Reads the scenes and chooses the work (validated before any work starts); -1 to go on, else the
// exit code.
int planExtremes(const StudyOptions& o, ExtremeWork& w) {
    std::string why;
    if (!loadSceneNamed(o.extremeScenePath, w.demo, why)) return usageError("--extreme-scene: " + why);
    // The stiff scene's flag, for the stiff_* configurations: the same cases with a flag ten
    // times stiffer.
    if (!loadSceneNamed("flag_vehicle_stiff", w.stiff, why)) {  // an installed tree missing it, or a bad edit
        std::fprintf(stderr, "cloth_study: the stiff_* configurations' scene: %s\n", why.c_str());
        return 1;
    }
    w.configs = configurations(o, w.demo, w.stiff, &why);
    if (w.configs.empty()) return usageError(why);
    std::string unknown;
    if (!chooseByName(w.configs, o.configFilter, unknown)) return usageError("--configs: unknown configuration '" + unknown + "'");
    if (!chooseByName(w.cases, o.caseFilter, unknown)) return usageError("--cases: unknown extreme case '" + unknown + "'");
    w.sizes = !o.extremeSizes.empty() ? o.extremeSizes : o.quick ? std::vector<int>{33} : std::vector<int>{33, 65};
    return -1;
}

}  // namespace

int main(int argc, char** argv) {
    StudyOptions o;
    if (const int code = parseOptions(argc, argv, o); code >= 0) return code;
    ExtremeWork w;
    if (const int code = planExtremes(o, w); code >= 0) return code;
    std::filesystem::create_directories(o.out);
    if (o.doExtremes && !extremeCasesDriveTheFlag(w.demo, o.exportDir.empty() ? o.out + "/extreme_cases.csv" : "")) return 1;
    const auto t0 = Clock::now();
    const SolveErrorScenes scenes;
    std::vector<SolveErrorConfig> configs = solveErrorConfigs(o, scenes);
    if (!o.exportDir.empty()) return exportForNvidiaNewton(o, configs, w.demo, w.cases, w.sizes);
    if (o.extremesOnly) configs.clear();
    WorkItems work{o.shard, o.shards};
    const long configRows = runSolveError(o, configs, work);
    const double seconds = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); }();
    if (!o.doExtremes) {
        writeShardInfo(o, configRows, 0);
        std::fprintf(stderr, "\nstudy done in %.0f s: %s/error_vs_runtime.csv\n", seconds, o.out.c_str());
        return 0;
    }
    const long extremeRows = runExtremes(o, w.demo, w.stiff, w.cases, w.sizes, w.configs, work);
    writeShardInfo(o, configRows, extremeRows);
    std::fprintf(stderr, "\nstudy done in %.0f s: %s/error_vs_runtime.csv, %s/extreme.csv\n",
                 std::chrono::duration<double>(Clock::now() - t0).count(), o.out.c_str(), o.out.c_str());
    return 0;
}
