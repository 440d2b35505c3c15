#include "front.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>

#include "bounds.h"
#include "reference_cache.h"
#include "specs.h"

namespace study {

namespace {

// The reference's substeps per 240 Hz tick at 33 per side (extreme_runs.h scales them with the
// size and the mass, and paces them by the pins' moves): the demo's soft flag, and the stiff flag
// (k = 1e4).
constexpr int kDemoReferenceSubsteps = 24, kStiffReferenceSubsteps = 160;

const char* const kHeader =
    "row,flag,path,size,config,solver,constraints,physics_hz,substeps,stable,failures,ms_per_tick,ms_per_frame,"
    "timing,traj_error,p99_stretch,peak_stretch,max_stretch,late_max_stretch,ke_patch_late,ref_p99_stretch,"
    "ref_peak_stretch,ref_ke_patch_late,energy_ratio,misses,iterations_mean,iterations_max,ke_mean,ke_late,"
    "ke_patch4_late,ke_patch16_late,ke_windows,max_speed,crossings,crossing_ticks\n";

// A CSV line built field by field (numbers with 4 significant digits, as the study prints them).
class Line {
public:
    Line& text(const std::string& s) { return add(s); }
    Line& quoted(const std::string& s) { return add("\"" + s + "\""); }
    Line& integer(long v) { return add(std::to_string(v)); }
    Line& number(double v) {
        char b[32];
        std::snprintf(b, sizeof b, "%.4g", v);
        return add(b);
    }
    std::string str() const { return line_ + "\n"; }

private:
    Line& add(const std::string& field) {
        if (!first_) line_ += ',';
        line_ += field;
        first_ = false;
        return *this;
    }
    std::string line_;
    bool first_ = true;
};

std::string windowsOf(const ExtremeRun& r) {
    std::string out;
    char b[32];
    for (double e : r.energyWindows) {
        std::snprintf(b, sizeof b, "%.4g", e);
        if (!out.empty()) out += ';';
        out += b;
    }
    return out;
}

// One group of rows: a path, a size and a flag, with that flag's reference computed once.
class FrontGroup {
public:
    FrontGroup(const Flags& flags, const Extreme& x, int size, FlagKind flag, const StudyOptions& o, ReferenceCache& cache)
        : flags_(flags), x_(x), size_(size), flag_(flag), trajectories_(o.trajectories && size <= o.trajectoryMaxSide),
          references_(o.references), cache_(cache) {}

    // What failed in the last row's run ("" when no tick failed): for its progress line.
    const std::string& failure() const { return failure_; }

    // This group's rows start with "FLAG PATH SIZE".
    std::string label() const { return std::string(flagName(flag_)) + " " + x_.name + " " + std::to_string(size_); }

    std::string row(long index, const Configuration& c, const char* timing) {
        const engine::SceneConfig s = sceneOf(c);
        const bool isReference = c.referenceFactor == 1 && !c.springsOnly && c.paced;
        const ExtremeRun none = noReference();
        const ExtremeRun& ref = references_ || isReference ? reference() : none;
        std::optional<ExtremeRun> own;
        if (!isReference) own = runExtreme(s, extremeMount(flags_.demo), x_, false);
        const ExtremeRun& r = isReference ? ref : *own;
        failure_ = r.failures > 0 ? std::to_string(r.failures) + " failed ticks, the first: " + r.firstFailure : "";
        const double traj = isReference ? 0.0 : trajectories_ && r.stable ? trajectoryError(s) : NAN;
        return format(index, c, s, r, ref, traj, timing);
    }

private:
    engine::SceneConfig sceneOf(const Configuration& c) const {
        engine::SceneConfig s = baseSceneOf(c);
        if (s.flag.contact.enabled) {
            s.flag.contact.substepStride = c.contactStride;
            s.flag.contact.strideMove = c.contactStrideMove;
            if (c.halfSpaces) s.flag.contact.selfBounds = cloth::ContactSettings::SelfBounds::HalfSpaces;
        }
        return s;
    }

    engine::SceneConfig baseSceneOf(const Configuration& c) const {
        const engine::SceneConfig& flag = flags_.of(flag_);
        engine::SceneConfig s = extremeScene(flag, x_, size_);
        if (c.shipped) return s;
        if (c.referenceFactor > 0) {
            const int base = flag_ == FlagKind::Demo ? kDemoReferenceSubsteps : kStiffReferenceSubsteps;
            const std::vector<Eigen::Vector3d> pins = c.paced ? pinnedColumn(s, extremeMount(flags_.demo))
                                                               : std::vector<Eigen::Vector3d>{};
            return referenceScene(s, c.referenceFactor * referenceSubsteps(base, size_, x_, pins), c.springsOnly);
        }
        s.flag.solver = configOf(c.solver);
        if (c.constraints) s.flag.constraints = constraintsOf(*c.constraints);
        s.flag.substeps = c.substeps;
        if (c.implicitAir >= 0) s.flag.implicitAir = c.implicitAir == 1;
        s.physicsHz = c.hz;
        return s;
    }

    // Without references: NaN figures, so every bound reads as missed; the misses column is then
    // left empty (format).
    static ExtremeRun noReference() {
        ExtremeRun r;
        r.p99Stretch = r.peakStretch = NAN;
        r.patchEnergyLate.fill(NAN);
        return r;
    }

    // The flag's reference on this path: from the cache, or run and stored there.
    const ExtremeRun& reference() {
        if (reference_) return *reference_;
        const engine::SceneConfig s = sceneOf({.referenceFactor = 1});
        const engine::PoleMount mount = extremeMount(flags_.demo);
        const std::string key = referenceKey(s, mount, x_, trajectories_, integratorVersion());
        reference_ = cache_.get(key, [&] { return runExtreme(s, mount, x_, trajectories_); });
        return *reference_;
    }

    double trajectoryError(const engine::SceneConfig& s) {
        const ExtremeRun& ref = reference();
        return horizonError(s, extremeMount(flags_.demo), x_, ref.states, x_.duration / double(ref.states.size() - 1));
    }

    std::string format(long index, const Configuration& c, const engine::SceneConfig& s, const ExtremeRun& r,
                       const ExtremeRun& ref, double traj, const char* timing) const {
        Line l;
        l.integer(index).text(flagName(flag_)).text(x_.name).integer(size_).text(c.name);
        l.quoted(c.referenceFactor > 0 ? "reference" : cloth::describe(s.flag.solver)).quoted(s.flag.constraints.describe());
        l.integer(s.physicsHz).integer(s.flag.substeps).integer(r.stable ? 1 : 0).integer(r.failures);
        const double ms = c.timing ? r.msPerTickProfiled : r.msPerTick;
        l.number(ms).number(ms * s.physicsHz / 60).text(c.timing ? c.timing : timing).number(traj);
        l.number(r.p99Stretch).number(r.peakStretch).number(r.maxStretch).number(r.lateStretch).number(r.patchEnergyLate[0]);
        l.number(ref.p99Stretch).number(ref.peakStretch).number(ref.patchEnergyLate[0]);
        l.number(r.patchEnergyLate[0] / ref.patchEnergyLate[0]).text(references_ ? missedBounds(r, ref, x_) : "");
        l.number(r.iterationsMean).integer(r.iterationsMax).number(r.energyMean).number(r.energyLate);
        l.number(r.patchEnergyLate[1]).number(r.patchEnergyLate[2]).text(windowsOf(r)).number(r.maxSpeed);
        l.integer(r.crossingsMax).integer(r.crossingTicks);
        return l.str();
    }

    const Flags& flags_;
    const Extreme& x_;
    int size_;
    FlagKind flag_;
    bool trajectories_, references_;
    ReferenceCache& cache_;
    std::optional<ExtremeRun> reference_;
    std::string failure_;
};

// What the cache did for the rows just run: "reference reused", "reference computed", or "".
std::string cacheNote(const CacheCounts& before, const CacheCounts& after) {
    if (after.reused > before.reused) return "reference reused";
    if (after.computed > before.computed) return after.refused > before.refused ? "reference refused, recomputed" : "reference computed";
    return {};
}

}  // namespace

bool pathsDriveTheFlag(const engine::SceneConfig& demo, const std::vector<Extreme>& paths, const std::string& csv) {
    const std::vector<CaseMotion> motions = caseMotions(demo, paths);
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

namespace {

// fn(row, group, configuration) for every row of the front, in the serial order.
template <class Fn>
void forEachRow(const FrontPlan& plan, ReferenceCache& cache, Fn fn) {
    long row = -1;
    for (const Extreme& x : plan.paths)
        for (const int size : plan.sizes)
            for (const FlagKind flag : plan.flagKinds) {
                FrontGroup group(plan.flags, x, size, flag, plan.options, cache);
                for (const Configuration& c : plan.configs)
                    if (c.runsOn(flag, size)) fn(++row, group, c);
            }
}

}  // namespace

long frontRows(const FrontPlan& plan, WorkItems work) {
    ReferenceCache none;
    long mine = 0;
    forEachRow(plan, none, [&](long, FrontGroup&, const Configuration&) { mine += work.mine(); });
    return mine;
}

long runFront(const FrontPlan& plan, WorkItems& work, ReferenceCache& cache, Progress& progress) {
    const StudyOptions& o = plan.options;
    std::ofstream csv(o.out + "/front.csv");
    csv << kHeader;
    const char* timing = o.parallel ? "parallel" : "serial";
    long rows = 0;
    forEachRow(plan, cache, [&](long row, FrontGroup& group, const Configuration& c) {
        rows = row + 1;
        if (!work.mine()) return;
        const std::string what = group.label() + " " + c.name;
        progress.begin(what);
        const CacheCounts before = cache.counts();
        const auto t0 = std::chrono::steady_clock::now();
        csv << group.row(row, c, timing) << std::flush;
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::string note = cacheNote(before, cache.counts());
        if (!group.failure().empty()) note += (note.empty() ? "" : "; ") + group.failure();
        progress.done(1, what, clockText(seconds) + (note.empty() ? "" : ", " + note));
    });
    return rows;
}

}  // namespace study
