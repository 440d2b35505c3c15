#include "runtime/summary.h"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/files/atomic_file.h"

namespace engine {

bool writeSummary(const std::string& path, const RunFacts& f, const Profiler& profiler,
                  std::string* error) {
    nlohmann::json j;
    j["scene"] = f.scene;
    j["subsystems"] = f.subsystems;
    j["solver"] = f.solver;
    j["anti_aliasing"] = f.antiAliasing;
    j["script"] = f.script;
    j["frames"] = f.frames;
    j["resolution"] = {f.width, f.height};
    j["sim_time_s"] = f.simTime;
    j["wall_time_s"] = f.wallSeconds;
    j["stop_reason"] = f.stopReason;
    j["cloth"] = {{"steps", f.clothSteps},
                  {"failures", f.clothFailures},
                  {"first_failure", f.firstClothFailure},
                  {"max_pin_error_m", f.maxPinError},
                  {"iterations_mean", f.iterationsMean},
                  {"iterations_max", f.iterationsMax},
                  {"linear_iterations_mean", f.linearIterationsMean}};
    j["recording"] = {{"frames_written", f.framesWritten}, {"video", f.video}, {"error", f.writerError}};
    if (f.crossingsCounted)
        j["crossings"] = {{"counted_after", f.crossingsEveryTick ? "every tick" : "each frame's ticks"},
                          {"counts", f.crossings.checks},
                          {"counts_with_crossings", f.crossings.withAny},
                          {"max_in_one_count", f.crossings.max},
                          {"at_the_worst_count", {{"pole_edges", f.crossings.worst.poleEdges},
                                                 {"self_edges", f.crossings.worst.selfEdges},
                                                 {"body_edges", f.crossings.worst.bodyEdges},
                                                 {"ground_particles", f.crossings.worst.groundParticles}}}};
    if (f.contactOn)
        j["contact"] = {{"applications", f.contact.applications}, {"subintervals", f.contact.subintervals},
                        {"self_pairs", f.contact.selfPairs},
                        {"near_solids", f.contact.near}, {"moves_limited", f.contact.limited},
                        {"region_cuts", f.contact.regionCuts}, {"extra_passes", f.contact.passes},
                        {"overloaded_steps", f.contact.overloaded}, {"broad_phase_ms", f.contact.broadPhaseMs}};
    if (!f.meshDir.empty())
        j["export_mesh"] = {{"dir", f.meshDir}, {"files_written", f.meshesWritten}, {"error", f.meshError}};
    nlohmann::json phases = nlohmann::json::object();
    const auto cols = profiler.columns();
    const auto stats = profiler.summary();
    for (std::size_t c = 0; c < cols.size(); ++c)
        phases[cols[c]] = {{"mean_ms", stats[c].mean}, {"p50_ms", stats[c].p50},
                           {"p95_ms", stats[c].p95},   {"p99_ms", stats[c].p99},
                           {"max_ms", stats[c].max}};
    j["profile"] = std::move(phases);
    return writeFileAtomically(path, j.dump(2) + "\n", error);
}

}  // namespace engine
