#include "study_options.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "extreme_cases.h"

namespace study {

namespace {

const char* const kUsage = R"(usage: cloth_study [options]

The solver study. Part 1, the solve error: every solver against the converged backward Euler step
on a hanging flag and on a flag following the demo's vehicle path, and a scan over stiffness and
time step (error_vs_runtime.csv). The front: the demo's flag and the stiff flag on the demo's drive
and in six extreme cases, every configuration against the flag's fine-step reference (front.csv).

  --quick              small: part 1 at size 17 (three stiffnesses, two more steps, 0.5 s); the
                       front with the demo's flag at 33x33 on the drive and the 10 g stop: its
                       reference, the paper's step as shipped, the true motion (small_steps_paced)
                       and one cheap configuration of each other family
  --out DIR            where the CSV files go (default out/study)
  --scenes LIST        part 1: comma-separated subset of hanging_flag, vehicle_path
  --sizes LIST         part 1: comma-separated grid sides, e.g. 17,33,65,129
  --solvers LIST       part 1: semicolon-separated solver specs to run instead of the default set,
                       e.g. "multigrid;multigrid:cycles=1;exact" (family = the name before ':')
  --no-scan            part 1 without the stiffness and time-step scan
  --no-front           no front (front.csv)
  --front-only         only the front
  --no-trajectories    no traj_error in the front (no restarted runs against the references)
  --trajectories-up-to N
                       traj_error on flags of up to N per side (default 33: above it each restart
                       of the reference costs as much again as the row)
  --no-references      no references in the front: no traj_error, ref_* columns or bounds (misses
                       empty), only each configuration's own figures (a quick check of stability)
  --flags LIST         the front's flags: demo, stiff (default both)
  --paths LIST         the front's paths: drive and the extreme cases (speed_50mps, stop_10g,
                       spin_5radps, teleport_1m, light_particles, gale_40mps)
  --teleports LIST     more paths: teleports of other lengths, comma-separated, in m (0 < d <= 10,
                       not 1), each a path teleport_<d>m (e.g. teleport_0.9m) like teleport_1m:
                       how much of one trajectory's figures is the chaos after the jump (with
                       --paths, name them there too)
  --configs LIST       comma-separated subset of the front's configurations (by name)
  --add-configs L      more configurations: NAME=SPEC@HZ or NAME=SPEC@HZxSUBSTEPS, ';'-separated
                       (e.g. "bdf2_90=newton:integrator=bdf2@90"); pick them with --configs
  --front-sizes LIST   flag sides of the front (default 33,65, --quick 33; the flag keeps its aspect)
  --demo-scene S       the demo's flag (a scene name or a .json path; default flag_vehicle): its
                       size, mass, stiffness, constraints, air, vehicle and drive script, and, as
                       `shipped`, its solver
  --contact            both flags with contact (flag.contact: no edge through the pole or the flag
                       itself), in every configuration and in their references (the front's rows
                       then answer for the model with contact; keep them in another --out);
                       without it, no contact, whatever the scenes' flag.contact says; with it
                       more configurations: the demo flag's small_steps_paced_tick and
                       shipped_half_spaces (contact once per tick, self pairs bounded by
                       half-spaces), both flags' small_steps_paced_stride2 (contact after every
                       second substep), the stiff flag's small_steps_paced_stride4 and
                       small_steps_paced_stride8 (every fourth and every eighth), and each
                       flag's stride once the flag has also moved 1 or 2 cm on its pole
                       (small_steps_paced_stride2_move1cm, small_steps_paced_stride2_move2cm,
                       small_steps_paced_stride4_move2cm)
  --nvidia-newton      NVIDIA Newton's VBD, XPBD and Style3D in the front too, stepped by a Python
                       process of the project's venv (.venv-nvidia-newton, or the Python in
                       FLAGSIM_NVIDIA_NEWTON_PYTHON; tools/run study --nvidia-newton makes it):
                       nvidia_newton_vbd, nvidia_newton_xpbd, nvidia_newton_style3d; their cost
                       is Newton's step as the process times it (timing=warp_cpu) plus the
                       library's air, constraints and contact
  --shard K/N          run only the K-th of N disjoint parts of the work (rows keep their serial
                       numbers; tools/study/study.py merge-shards joins the parts)
  --export-nvidia-newton DIR
                       write the flag and pole motion of every k=1e4, h=1/240 configuration, and of
                       every path and size of the front (--quick: the teleport), as JSON for NVIDIA
                       Newton's harness (tools/study/study.py nvidia-newton), then stop
  --parallel           mark the timing columns as taken while other shards ran (timing=parallel)
  --cache-dir DIR      where the front's references are kept and reused (default out/study-cache
                       in the source tree): each under a key of everything that determines it,
                       recomputed when any of it changes, refused and recomputed when corrupt
  --no-cache           compute every reference, reuse and store none
  --progress-lines     a progress line per row even on a terminal (else one line updated in place)
  --help               this text
)";


// A comma-separated list of grid sides in [lo, hi] into `out`; the error names the option and the
// value, or is empty.
std::string readSides(const std::string& option, const std::string& text, long lo, long hi, std::vector<int>& out) {
    for (const std::string& v : split(text, ',')) {
        char* end = nullptr;
        const long n = std::strtol(v.c_str(), &end, 10);
        if (*end != '\0' || n < lo || n > hi)
            return option + ": '" + v + "' is not a side in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        out.push_back(int(n));
    }
    return {};
}

// A comma-separated list of teleport lengths into `out`; the error names the value, or is empty.
std::string readTeleports(const std::string& text, std::vector<double>& out) {
    for (const std::string& v : split(text, ',')) {
        char* end = nullptr;
        const double d = std::strtod(v.c_str(), &end);
        if (*end != '\0' || !(d > 0 && d <= 10) || teleportName(d) == teleportName(1))
            return "--teleports: '" + v + "' is not a length in (0, 10] m other than 1 (teleport_1m is a case already)";
        const auto same = [&](double e) { return teleportName(e) == teleportName(d); };  // paths go by name
        if (std::any_of(out.begin(), out.end(), same)) return "--teleports: '" + v + "' names " + teleportName(d) + " twice";
        out.push_back(d);
    }
    return {};
}

// The option at argv[i] that takes a value (the value at argv[++i]); -1 to go on, else an exit code.
int readValueOption(const std::string& a, const char* value, StudyOptions& o) {
    if (a == "--export-nvidia-newton") o.exportDir = value;
    else if (a == "--configs") o.configFilter = split(value, ',');
    else if (a == "--paths") o.pathFilter = split(value, ',');
    else if (a == "--flags") o.flagFilter = split(value, ',');
    else if (a == "--add-configs") o.extraConfigs = split(value, ';');
    else if (a == "--demo-scene") o.demoScenePath = value;
    else if (a == "--out") o.out = value;
    else if (a == "--cache-dir") o.cacheDir = value;
    else if (a == "--trajectories-up-to") {
        std::vector<int> side;
        if (const std::string bad = readSides(a, value, 5, 257, side); !bad.empty() || side.size() != 1)
            return usageError(bad.empty() ? a + ": one side" : bad);
        o.trajectoryMaxSide = side.front();
    }
    else if (a == "--shard") {
        const std::string v = value;
        if (std::sscanf(v.c_str(), "%d/%d", &o.shard, &o.shards) != 2 || o.shards < 1 || o.shards > 1000 || o.shard < 1 ||
            o.shard > o.shards || v.find_first_not_of("0123456789/") != std::string::npos)
            return usageError("--shard: '" + v + "' is not K/N with 1 <= K <= N <= 1000");
    } else if (a == "--teleports") {
        if (const std::string bad = readTeleports(value, o.teleports); !bad.empty()) return usageError(bad);
    } else if (a == "--front-sizes") {
        if (const std::string bad = readSides(a, value, 5, 257, o.frontSizes); !bad.empty()) return usageError(bad);
    } else if (a == "--scenes") {
        o.sceneFilter = split(value, ',');
        for (const std::string& sc : o.sceneFilter)
            if (sc != "hanging_flag" && sc != "vehicle_path") return usageError("--scenes: unknown scene '" + sc + "'");
    } else if (a == "--sizes") {
        if (const std::string bad = readSides(a, value, 3, 513, o.sizeOverride); !bad.empty()) return usageError(bad);
    } else if (a == "--solvers") {
        o.solverSpecs = split(value, ';');
        for (const std::string& spec : o.solverSpecs) {
            cloth::SolverConfig c;
            std::string error;
            if (!cloth::parseSolverConfig(spec, c, &error)) return usageError("--solvers: " + error);
        }
    } else return usageError("unknown or incomplete option '" + a + "'");
    return -1;
}

}  // namespace

int usageError(const std::string& why) {
    std::fprintf(stderr, "cloth_study: %s\n%s", why.c_str(), kUsage);
    return 2;
}

int parseOptions(int argc, char** argv, StudyOptions& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            std::fputs(("\n--solvers takes these (name[:key=value,...]):\n" + cloth::solverHelp()).c_str(), stdout);
            return 0;
        } else if (a == "--quick") o.quick = true;
        else if (a == "--front-only") o.frontOnly = true;
        else if (a == "--no-scan") o.scan = false;
        else if (a == "--no-front") o.front = false;
        else if (a == "--no-trajectories") o.trajectories = false;
        else if (a == "--no-references") o.references = o.trajectories = false;
        else if (a == "--parallel") o.parallel = true;
        else if (a == "--no-cache") o.cacheDir.clear();
        else if (a == "--progress-lines") o.progressLines = true;
        else if (a == "--contact") o.contact = true;
        else if (a == "--nvidia-newton") o.nvidiaNewton = true;
        else if (i + 1 >= argc) return usageError("unknown or incomplete option '" + a + "'");
        else if (const int code = readValueOption(a, argv[++i], o); code >= 0) return code;
    }
    return -1;
}

std::vector<std::string> split(const std::string& text, char sep) {
    std::vector<std::string> parts;
    std::size_t at = 0;
    while (at <= text.size()) {
        const std::size_t next = text.find(sep, at);
        const std::string part = text.substr(at, next == std::string::npos ? std::string::npos : next - at);
        if (!part.empty()) parts.push_back(part);
        if (next == std::string::npos) break;
        at = next + 1;
    }
    return parts;
}

}  // namespace study
