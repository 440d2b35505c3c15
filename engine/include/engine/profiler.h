#pragma once
// Frame profile: milliseconds per named phase per frame. A scene registers only the phases of
// the subsystems it uses, so the profile shows exactly what its frame pays for. Bullet's own
// profile zones can be routed in as extra columns ("bullet:<zone>"). Given a Trace, it also
// records each frame, each timed phase and each Bullet zone (every level) as an event, with the
// same clock readings as the profile.

#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "engine/trace.h"

namespace engine {

class Profiler {
public:
    using Clock = std::chrono::steady_clock;

    // Registers a phase; returns its id. Phases keep their registration order.
    int addPhase(const std::string& name);
    int phaseId(const std::string& name) const;  // -1 when absent
    const std::vector<std::string>& phases() const { return names_; }

    // Events go to trace from now on (null: none). The trace must outlive the recording.
    void setTrace(Trace* trace);

    void beginFrame();
    void add(int phase, double ms) { current_[phase] += ms; }
    void endFrame();  // closes the row; "frame" is the wall time from beginFrame

    // RAII timer for one phase.
    class Scope {
    public:
        Scope(Profiler& p, int phase) : p_(p), phase_(phase), t0_(Clock::now()) {}
        ~Scope() {
            const Clock::time_point t1 = Clock::now();
            p_.add(phase_, ms(t1 - t0_));
            if (p_.trace_) p_.tracePhase(phase_, t0_, t1);
        }
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

    private:
        Profiler& p_;
        int phase_;
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
    std::size_t frameCount() const { return rows_.size(); }
    // Column names: the phases, then "frame".
    std::vector<std::string> columns() const;
    std::vector<Stats> summary() const;
    const std::vector<std::vector<double>>& rows() const { return rows_; }

    // CSV: "frame_index,<phase>...,frame" then one row per frame. Written to a temporary name and
    // renamed. Returns false with *error set on failure.
    bool writeCsv(const std::string& path, std::string* error) const;
    // A fixed-width table of the summary for the terminal.
    std::string summaryTable() const;

private:
    void tracePhase(int phase, Clock::time_point t0, Clock::time_point t1);

    std::vector<std::string> names_;
    std::vector<double> current_;
    std::vector<std::vector<double>> rows_;
    Clock::time_point frameStart_;
    struct OpenZone {
        int phase;
        Clock::time_point t0;
        const char* name;
    };
    std::vector<OpenZone> zones_;
    Trace* trace_ = nullptr;
    std::vector<int> traceNames_;  // each phase's name id in trace_ (-1: not asked for yet)
    int traceFrameName_ = -1;
};

}  // namespace engine
