// cloth_study: error against run time, and stability on stiff and extreme cases.
//
//   cloth_study [--quick] [--out DIR]      (tools/run study [--quick] runs it and plots)
//   cloth_study --help                     (every option: subsets of scenes, sizes and solvers)
//
// Part 1 (solve_error.h, error_vs_runtime.csv): every solver on the same cloth against the
// converged backward Euler step. The front (front.h, front.csv): the demo's flag and the stiff
// scene's flag on the demo's drive and in extreme cases, per configuration (configurations.h),
// against each flag's fine-step reference. --export-nvidia-newton writes the same flags and pole motions for NVIDIA
// Newton's harness instead (nvidia_newton_export.h).

#include <algorithm>
#include <chrono>
#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bullet_kind.h"
#include "nvidia_newton_kind.h"
#include "configurations.h"
#include "drive_case.h"
#include "extreme_cases.h"
#include "front.h"
#include "nvidia_newton_export.h"
#include "solve_error.h"
#include "study_options.h"

using namespace study;

namespace {

using Clock = std::chrono::steady_clock;

// shard.json: which part of the work this run holds and how many rows the whole run has, so that
// `study.py merge-shards` can tell a complete set of shards from an incomplete one.
void writeShardInfo(const StudyOptions& o, long configRows, long frontRows) {
    std::ofstream f(o.out + "/shard.json");
    f << "{\"shard\": " << o.shard << ", \"of\": " << o.shards << ", \"rows\": {\"error_vs_runtime.csv\": " << configRows
      << ", \"front.csv\": " << frontRows << "}}\n";
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

// What the front runs: the two flags' scenes, the configurations, the flags, paths and sizes.
struct FrontWork {
    Flags flags;
    std::vector<Configuration> configs;
    std::vector<FlagKind> flagKinds = {FlagKind::Demo, FlagKind::Stiff};
    std::vector<Extreme> paths;
    std::vector<int> sizes;
};

struct Named {
    std::string name;
    FlagKind kind;
};

// The flags --flags names, in that order; false with the first unknown name.
bool chooseFlags(const std::vector<std::string>& names, std::vector<FlagKind>& out, std::string& unknown) {
    std::vector<Named> all = {{"demo", FlagKind::Demo}, {"stiff", FlagKind::Stiff}};
    if (!chooseByName(all, names, unknown)) return false;
    out.clear();
    for (const Named& n : all) out.push_back(n.kind);
    return true;
}

// The paths: the demo's drive, the extreme cases (--quick: the drive and the 10 g stop), then the
// teleports of --teleports.
std::vector<Extreme> pathsOf(const StudyOptions& o, const engine::SceneConfig& demo) {
    std::vector<Extreme> paths = {driveCase(demo)};
    for (const Extreme& x : extremes()) paths.push_back(x);
    if (o.quick && o.pathFilter.empty())
        std::erase_if(paths, [](const Extreme& x) { return x.name != "drive" && x.name != "stop_10g"; });
    for (double metres : o.teleports) paths.push_back(teleport(metres));
    return paths;
}

// Reads the scenes and chooses the work (validated before any work starts); -1 to go on, else the
// exit code.
int planFront(const StudyOptions& o, FrontWork& w) {
    std::string why;
    if (!loadSceneNamed(o.demoScenePath, w.flags.demo, why)) return usageError("--demo-scene: " + why);
    if (!loadSceneNamed("flag_vehicle_stiff", w.flags.stiff, why)) {  // an installed tree missing it, or a bad edit
        std::fprintf(stderr, "cloth_study: the stiff flag's scene: %s\n", why.c_str());
        return 1;
    }
    for (engine::SceneConfig* s : {&w.flags.demo, &w.flags.stiff}) *s = withContact(*s, o.contact);
    w.configs = configurations(o, &why);
    if (w.configs.empty()) return usageError(why);
    std::string unknown;
    if (!chooseByName(w.configs, o.configFilter, unknown)) return usageError("--configs: unknown configuration '" + unknown + "'");
    if (!chooseFlags(o.flagFilter, w.flagKinds, unknown)) return usageError("--flags: unknown flag '" + unknown + "'");
    if (o.quick && o.flagFilter.empty()) w.flagKinds = {FlagKind::Demo};  // the demo's flag: the paper's step
    w.paths = pathsOf(o, w.flags.demo);
    if (!chooseByName(w.paths, o.pathFilter, unknown)) return usageError("--paths: unknown path '" + unknown + "'");
    w.sizes = !o.frontSizes.empty() ? o.frontSizes : o.quick ? std::vector<int>{33} : std::vector<int>{33, 65};
    return -1;
}

// The rows this run will write: part 1's and the front's that are this shard's.
long plannedRows(const StudyOptions& o, const std::vector<SolveErrorConfig>& configs, const FrontPlan& plan) {
    WorkItems work{o.shard, o.shards};
    const long part1 = solveErrorRows(o, configs, work);
    return part1 + (o.front ? frontRows(plan, work) : 0);
}

// Why a planned configuration cannot run here ("" when all can): NVIDIA Newton's without its venv.
std::string peersUnavailable(const FrontWork& w) {
    const bool newton = std::any_of(w.configs.begin(), w.configs.end(),
                                    [](const Configuration& c) { return c.solver.rfind("nvidia_newton", 0) == 0; });
    return newton ? nvidiaNewtonUnavailable() : std::string();
}

// After a failed run: the CSVs it was writing renamed to NAME.partial, so that none looks whole.
void setAsidePartialOutputs(const StudyOptions& o) {
    for (const char* name : {"front.csv", "error_vs_runtime.csv"}) {
        const std::filesystem::path p = std::filesystem::path(o.out) / name;
        std::error_code ec;
        if (!std::filesystem::exists(p, ec)) continue;
        std::filesystem::rename(p, p.string() + ".partial", ec);
        std::fprintf(stderr, "cloth_study: the rows written so far are in %s.partial\n", p.c_str());
    }
}

// The run: part 1 and the front (or the export for NVIDIA Newton's harness); the exit code.
int run(const StudyOptions& o, const FrontWork& w) {
    std::filesystem::create_directories(o.out);
    if (o.front && !pathsDriveTheFlag(w.flags.demo, w.paths, o.exportDir.empty() ? o.out + "/extreme_cases.csv" : ""))
        return 1;
    const SolveErrorScenes scenes;
    std::vector<SolveErrorConfig> configs = solveErrorConfigs(o, scenes);
    if (!o.exportDir.empty()) return exportForNvidiaNewton(o, configs, w.flags.demo, w.paths, w.sizes);
    if (o.frontOnly) configs.clear();
    const FrontPlan plan{o, w.flags, w.flagKinds, w.paths, w.sizes, w.configs};
    WorkItems work{o.shard, o.shards};
    ReferenceCache cache(o.cacheDir);
    Progress progress(plannedRows(o, configs, plan), isatty(fileno(stderr)) && !o.progressLines);
    const long configRows = runSolveError(o, configs, work, progress);
    const long frontRows = o.front ? runFront(plan, work, cache, progress) : 0;
    writeShardInfo(o, configRows, frontRows);
    std::string written = o.frontOnly ? "" : o.out + "/error_vs_runtime.csv";
    if (o.front) written += (written.empty() ? "" : ", ") + o.out + "/front.csv";
    const CacheCounts& c = cache.counts();
    progress.finish("references: " + std::to_string(c.reused) + " reused, " + std::to_string(c.computed) + " computed" +
                    (c.refused ? ", " + std::to_string(c.refused) + " refused" : "") +
                    (cache.on() ? " (cache " + o.cacheDir + ")" : " (no cache)") + "; " + written);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    registerBulletSoftBody();  // before the options: --add-configs and --help may name them
    registerNvidiaNewton();
    StudyOptions o;
    if (const int code = parseOptions(argc, argv, o); code >= 0) return code;
    FrontWork w;
    if (const int code = planFront(o, w); code >= 0) return code;
    if (const std::string why = peersUnavailable(w); !why.empty()) return usageError(why);
    try {
        return run(o, w);
    } catch (const std::exception& e) {  // a peer's process that failed: its reason, and no CSV that looks whole
        std::fprintf(stderr, "\ncloth_study: %s\n", e.what());
        setAsidePartialOutputs(o);
        return 1;
    }
}
