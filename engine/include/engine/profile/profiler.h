#pragma once
// Frame profile: milliseconds per phase per frame. The phases are a fixed list (Phase), as
// Box2D's b2Profile names each stage of its step; a scene enables only the phases of the
// subsystems it uses, so the profile shows exactly what its frame pays for, and a phase it does
// not enable is not timed at all. Bullet's own profile zones can be routed in as extra columns
// ("bullet:<zone>"). Given a Trace, it also records each frame, each timed phase and each Bullet
// zone (every level) as an event, with the same clock readings as the profile.

#include <array>
#include <chrono>
#include <string>
#include <vector>

#include "engine/profile/trace.h"

namespace engine {

// The frame's phases, in the order they run (and of the profile's columns).
enum class Phase {
    Input,        // the window's events, the commands, the actions                [vehicle]
    Bullet,       // one Bullet tick per physics tick                               [vehicle]
    Air,          // the air on the flag                                            [air]
    ClothForces,  // the solver's forces, Jacobian blocks and right-hand side      [cloth]
    ClothSolve,   // the solver's solve, integration and the cloth's constraints    [cloth]
    Collision,    // the flag against the pole, the vehicle and the ground          [collision]
    Contact,      // the flag's edges kept out of the solids and out of itself    [flag.contact]
    Crossings,    // the flag's crossings counted (cloth/crossings.h)               [collision]
    Render,       // the scene drawn                                                [render]
    Overlay,      // the panel drawn into the recorded frames                       [--overlay]
    Readback,     // glFinish and the pixels read back                              [render]
    AntiAlias,    // the post pass over the pixels read back                        [render.aa = post]
    Panel,        // the panel drawn on screen only                                 [window]
    Write,        // the frame handed to the PNG and video writers                  [recording]
    ExportMesh,   // the flag's mesh written as DIR/flag_NNNNNN.obj                 [--export-mesh]
};
inline constexpr int kPhaseCount = 15;
const char* phaseName(Phase phase);  // "input", "bullet", "cloth_forces", ...

// One frame's milliseconds in each phase (0 in a phase the scene does not enable) and in all.
struct FrameProfile {
    std::array<double, kPhaseCount> phase{};
    double frame = 0;
    double& operator[](Phase p) { return phase[std::size_t(p)]; }
    double operator[](Phase p) const { return phase[std::size_t(p)]; }
};

class Profiler {
public:
    using Clock = std::chrono::steady_clock;

    // The scene has this phase: it is timed and has a column. Enable before the first frame.
    void enable(Phase phase);
    bool enabled(Phase phase) const { return enabled_[std::size_t(phase)]; }
    // The enabled phases' names, in Phase order.
    std::vector<std::string> phases() const;

    // Events go to trace from now on (null: none). The trace must outlive the recording.
    void setTrace(Trace* trace);

    void beginFrame();
    void add(Phase phase, double ms) {
        if (enabled(phase)) current_[phase] += ms;
    }
    void endFrame();  // closes the row; "frame" is the wall time from beginFrame
    // The last frame's profile (the panel shows it).
    const FrameProfile& lastFrame() const { return last_; }

    // RAII timer for one phase; nothing at all for a phase the scene does not enable.
    class Scope {
    public:
        Scope(Profiler& p, Phase phase) : p_(p.enabled(phase) ? &p : nullptr), phase_(phase) {
            if (p_) t0_ = Clock::now();
        }
        ~Scope() {
            if (!p_) return;
            const Clock::time_point t1 = Clock::now();
            p_->add(phase_, ms(t1 - t0_));
            if (p_->trace_) p_->tracePhase(phase_, t0_, t1);
        }
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

    private:
        Profiler* p_;
        Phase phase_;
        Clock::time_point t0_;
    };
    static double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }
    static double msSince(Clock::time_point t0) { return ms(Clock::now() - t0); }

    // Bullet zones (nested timing by name), see routeBulletProfileZones in the physics module.
    void enterZone(const char* name);
    void leaveZone();

    struct Stats {
        double mean = 0, p50 = 0, p95 = 0, p99 = 0, max = 0;
    };
    // Keeps the last `frames` rows only, at least (0: every row). A run that writes no profile
    // keeps its memory bounded this way however long it runs; its summary is of the last rows.
    void setRowLimit(std::size_t frames) { rowLimit_ = frames; }
    std::size_t frameCount() const { return framesEnded_; }  // every frame, kept or not
    // Column names: the enabled phases, Bullet's zones, then "frame".
    std::vector<std::string> columns() const;
    std::vector<Stats> summary() const;
    const std::vector<std::vector<double>>& rows() const { return rows_; }

    // CSV: "frame_index,<phase>...,frame" then one row per frame. Written to a temporary name and
    // renamed. Returns false with *error set on failure.
    bool writeCsv(const std::string& path, std::string* error) const;
    // A fixed-width table of the summary for the terminal.
    std::string summaryTable() const;

private:
    void tracePhase(Phase phase, Clock::time_point t0, Clock::time_point t1);
    int zoneColumn(const char* name);

    std::array<bool, kPhaseCount> enabled_{};
    std::vector<Phase> columns_;             // the enabled phases, in Phase order
    std::vector<std::string> zoneNames_;     // "bullet:<zone>", in the order first seen
    FrameProfile current_, last_;
    std::vector<double> currentZones_;
    std::vector<std::vector<double>> rows_;  // the enabled phases, the zones, the frame
    std::size_t rowLimit_ = 0, framesEnded_ = 0;
    Clock::time_point frameStart_;
    struct OpenZone {
        int column;  // in zoneNames_, or -1 (a level that is not a column)
        Clock::time_point t0;
        const char* name;
    };
    std::vector<OpenZone> zones_;
    Trace* trace_ = nullptr;
    std::array<int, kPhaseCount> traceNames_{};  // each phase's name id in trace_
    int traceFrameName_ = -1;
};

}  // namespace engine
