#include "front.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "extreme_runs.h"
#include "specs.h"

namespace study {

namespace {

// The reference's substeps per tick at 33 per side (extreme_runs.h scales them with the size and
// the mass): the demo's soft flag, and the stiff flag (k = 1e4).
constexpr int kDemoReferenceSubsteps = 24, kStiffReferenceSubsteps = 160;

// The extreme cases' rows: each case x size x configuration, the configurations judged against
// their flag's reference (computed once per case, size and flag).
class ExtremeStudy {
public:
    // trajectories: whether the configurations get traj_error (each a run against the reference).
    ExtremeStudy(const engine::SceneConfig& demo, const engine::SceneConfig& stiff, bool trajectories)
        : demo_(demo), stiff_(stiff), trajectories_(trajectories) {}
    // The patch energy columns name kPatchCounts in order.
    static_assert(kPatchCounts == std::array<int, 3>{8, 4, 16});
    static const char* header() {
        return "row,case,size,config,stable,failures,ms_per_tick,timing,max_stretch,peak_stretch,p99_stretch,"
               "late_max_stretch,max_speed,physics_hz,ke_mean,ke_late,ke_windows,traj_error,iterations_mean,"
               "iterations_max,ke_patch_late,ke_patch4_late,ke_patch16_late\n";
    }
    std::string row(long index, const Extreme& x, int size, const Configuration& v, const char* timing) {
        const engine::SceneConfig s = sceneOf(x, size, v);
        const engine::PoleMount mount = extremeMount(demo_);
        const bool needsReference = v.referenceFactor == 1 || trajectories_;
        const ExtremeRun* ref = needsReference ? &reference(x, size, v.stiff) : nullptr;
        ExtremeRun own;
        const ExtremeRun& r = v.referenceFactor == 1 ? *ref : (own = runExtreme(s, mount, x, false));
        const double traj = v.referenceFactor == 1 ? 0.0
                            : r.stable && ref ? horizonError(s, mount, x, ref->states, hOf(*ref, x))
                                              : NAN;
        std::string windows;
        for (double e : r.energyWindows) {
            if (!windows.empty()) windows += ';';
            windows += fmt(e);
        }
        char line[700];
        std::snprintf(line, sizeof line, "%ld,%s,%d,%s,%d,%d,%.4g,%s,%.4g,%.4g,%.4g,%.4g,%.4g,%g,%.4g,%.4g,%s,%.4g,%.4g,%d,%.4g,%.4g,%.4g\n",
                      index, x.name.c_str(), size, v.name.c_str(), r.stable ? 1 : 0, r.failures, r.msPerTick, timing,
                      r.maxStretch, r.peakStretch, r.p99Stretch, r.lateStretch, r.maxSpeed, double(s.physicsHz), r.energyMean,
                      r.energyLate, windows.c_str(), traj, r.iterationsMean, r.iterationsMax, r.patchEnergyLate[0],
                      r.patchEnergyLate[1], r.patchEnergyLate[2]);
        return line;
    }

private:
    static std::string fmt(double v) {
        char b[32];
        std::snprintf(b, sizeof b, "%.4g", v);
        return b;
    }
    static double hOf(const ExtremeRun& ref, const Extreme& x) { return x.duration / double(ref.states.size() - 1); }
    engine::SceneConfig sceneOf(const Extreme& x, int size, const Configuration& v) const {
        engine::SceneConfig s = extremeScene(v.stiff ? stiff_ : demo_, x, size);
        if (v.referenceFactor > 0) {
            const int base = v.stiff ? kStiffReferenceSubsteps : kDemoReferenceSubsteps;
            return referenceScene(s, v.referenceFactor * referenceSubsteps(base, size, x));
        }
        s.flag.solver = configOf(v.solver);
        s.flag.constraints = constraintsOf(v.constraints);
        s.flag.substeps = v.substeps;
        if (v.implicitAir >= 0) s.flag.implicitAir = v.implicitAir == 1;
        if (v.hz > 0) s.physicsHz = v.hz;
        return s;
    }
    const ExtremeRun& reference(const Extreme& x, int size, bool stiff) {
        const std::string key = x.name + "/" + std::to_string(size) + (stiff ? "/stiff" : "/demo");
        auto it = references_.find(key);
        if (it == references_.end()) {
            const Configuration ref{.name = "reference", .stiff = stiff, .referenceFactor = 1};
            it = references_.emplace(key, runExtreme(sceneOf(x, size, ref), extremeMount(demo_), x, true)).first;
        }
        return it->second;
    }
    const engine::SceneConfig& demo_;
    const engine::SceneConfig& stiff_;
    bool trajectories_;
    std::map<std::string, ExtremeRun> references_;
};


}  // namespace

bool extremeCasesDriveTheFlag(const engine::SceneConfig& demo, const std::string& csv) {
    const std::vector<CaseMotion> motions = caseMotions(demo, extremes());
    if (!csv.empty()) {
        std::ofstream f(csv);
        f << "case,wind,pin_speed_max,pin_accel_max\n";
        char line[200];
        for (const CaseMotion& c : motions) {
            std::snprintf(line, sizeof line, "%s,%g,%.4g,%.4g\n", c.name.c_str(), c.wind, c.pins.speedMax, c.pins.accelMax);
            f << line;
        }
    }
    const std::string idle = idleCases(motions);
    if (!idle.empty()) std::fprintf(stderr, "cloth_study: %s", idle.c_str());
    return idle.empty();
}


long runExtremes(const StudyOptions& o, const engine::SceneConfig& demo, const engine::SceneConfig& stiff,
                 const std::vector<Extreme>& cases, const std::vector<int>& sizes,
                 const std::vector<Configuration>& configs, WorkItems& work) {
    std::ofstream ext(o.out + "/extreme.csv");
    // peak_stretch: max_stretch without the 0.25 s after a jump of the pole (teleport);
    // p99_stretch: the largest per-tick 99th percentile; late_max_stretch: the last second;
    // ke_*: kinetic energy in the carrier's frame; traj_error: against the flag's reference.
    ext << ExtremeStudy::header();
    ExtremeStudy study(demo, stiff, o.trajectories);
    const char* timing = o.parallel ? "parallel" : "serial";
    long row = -1;
    for (const Extreme& x : cases)
        for (const int size : sizes)
            for (const Configuration& v : configs) {
                ++row;
                if (work.mine()) ext << study.row(row, x, size, v, timing) << std::flush;
            }
    return row + 1;
}

}  // namespace study
