#include "engine/profile/profiler.h"

#include "engine/files/atomic_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace engine {

const char* phaseName(Phase phase) {
    static const char* const names[kPhaseCount] = {"input",    "bullet",   "air",      "cloth_forces",
                                                   "cloth_solve", "collision", "contact", "crossings", "render",
                                                   "overlay",  "readback", "aa",       "panel",
                                                   "write", "export_mesh"};
    return names[std::size_t(phase)];
}

void Profiler::enable(Phase phase) {
    if (enabled(phase)) return;
    enabled_[std::size_t(phase)] = true;
    columns_.clear();
    for (int p = 0; p < kPhaseCount; ++p)
        if (enabled_[std::size_t(p)]) columns_.push_back(Phase(p));
}

std::vector<std::string> Profiler::phases() const {
    std::vector<std::string> names;
    for (const Phase p : columns_) names.push_back(phaseName(p));
    return names;
}

void Profiler::setTrace(Trace* trace) {
    trace_ = trace;
    traceNames_.fill(-1);
    traceFrameName_ = trace ? trace->nameId("frame") : -1;
}

void Profiler::tracePhase(Phase phase, Clock::time_point t0, Clock::time_point t1) {
    int& name = traceNames_[std::size_t(phase)];
    if (name < 0) name = trace_->nameId(phaseName(phase));
    trace_->complete(name, Trace::Category::Phase, t0, t1);
}

void Profiler::beginFrame() {
    current_ = {};
    std::fill(currentZones_.begin(), currentZones_.end(), 0.0);
    frameStart_ = Clock::now();
}

void Profiler::endFrame() {
    const Clock::time_point end = Clock::now();
    current_.frame = ms(end - frameStart_);
    std::vector<double> row;
    for (const Phase p : columns_) row.push_back(current_[p]);
    row.insert(row.end(), currentZones_.begin(), currentZones_.end());
    row.push_back(current_.frame);
    if (trace_)
        trace_->complete(traceFrameName_, Trace::Category::Frame, frameStart_, end, static_cast<int>(framesEnded_));
    // Past twice the limit, the oldest half goes: the rows stay within 2x the limit (its capacity).
    if (rowLimit_ > 0 && rows_.size() >= 2 * rowLimit_) rows_.erase(rows_.begin(), rows_.begin() + rowLimit_);
    rows_.push_back(std::move(row));
    ++framesEnded_;
    last_ = current_;
}

int Profiler::zoneColumn(const char* name) {
    const std::string column = std::string("bullet:") + name;
    const auto it = std::find(zoneNames_.begin(), zoneNames_.end(), column);
    if (it != zoneNames_.end()) return static_cast<int>(it - zoneNames_.begin());
    zoneNames_.push_back(column);
    currentZones_.push_back(0);
    return static_cast<int>(zoneNames_.size()) - 1;
}

// Only the second level of Bullet's zones is kept as columns: the first
// (internalSingleStepSimulation) is the whole tick, which the "bullet" phase already times, and
// deeper levels repeat their parents. A trace gets every level, named by Bullet.
void Profiler::enterZone(const char* name) {
    const int column = zones_.size() == 1 ? zoneColumn(name) : -1;
    zones_.push_back({column, Clock::now(), name});
}

void Profiler::leaveZone() {
    if (zones_.empty()) return;
    const OpenZone& z = zones_.back();
    if (z.column >= 0 || trace_) {  // a deeper zone only ends an event of a trace
        const Clock::time_point end = Clock::now();
        if (z.column >= 0) currentZones_[std::size_t(z.column)] += ms(end - z.t0);
        if (trace_) trace_->complete(trace_->staticNameId(z.name), Trace::Category::Zone, z.t0, end);
    }
    zones_.pop_back();
}

std::vector<std::string> Profiler::columns() const {
    std::vector<std::string> c = phases();
    c.insert(c.end(), zoneNames_.begin(), zoneNames_.end());
    c.push_back("frame");
    return c;
}

std::vector<Profiler::Stats> Profiler::summary() const {
    const std::size_t cols = columns_.size() + zoneNames_.size() + 1;
    std::vector<Stats> out(cols);
    if (rows_.empty()) return out;
    std::vector<double> v;
    for (std::size_t c = 0; c < cols; ++c) {
        v.clear();
        // A Bullet zone first seen mid-run is zero in the rows before it.
        for (const auto& row : rows_) v.push_back(c == cols - 1 ? row.back() : (c < row.size() - 1 ? row[c] : 0.0));
        std::sort(v.begin(), v.end());
        auto pct = [&v](double p) {  // nearest rank
            const std::size_t rank = static_cast<std::size_t>(std::ceil(p * v.size()));
            return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
        };
        double sum = 0;
        for (double x : v) sum += x;
        out[c] = {sum / v.size(), pct(0.50), pct(0.95), pct(0.99), v.back()};
    }
    return out;
}

bool Profiler::writeCsv(const std::string& path, std::string* error) const {
    std::ostringstream out;
    out << "frame_index";
    for (const auto& c : columns()) out << "," << c;
    out << "\n";
    char buf[32];
    const std::size_t first = framesEnded_ - rows_.size();  // the rows a limit let go came first
    for (std::size_t f = 0; f < rows_.size(); ++f) {
        out << first + f;
        const auto& row = rows_[f];
        for (std::size_t c = 0; c < columns_.size() + zoneNames_.size(); ++c) {
            std::snprintf(buf, sizeof buf, ",%.4f", c < row.size() - 1 ? row[c] : 0.0);
            out << buf;
        }
        std::snprintf(buf, sizeof buf, ",%.4f", row.back());
        out << buf << "\n";
    }
    return writeFileAtomically(path, out.str(), error);
}

std::string Profiler::summaryTable() const {
    std::ostringstream s;
    char line[160];
    std::snprintf(line, sizeof line, "%-36s %9s %9s %9s %9s %9s\n", "phase (ms)", "mean", "p50",
                  "p95", "p99", "max");
    s << line;
    const auto cols = columns();
    const auto stats = summary();
    for (std::size_t c = 0; c < cols.size(); ++c) {
        std::snprintf(line, sizeof line, "%-36s %9.3f %9.3f %9.3f %9.3f %9.3f\n", cols[c].c_str(),
                      stats[c].mean, stats[c].p50, stats[c].p95, stats[c].p99, stats[c].max);
        s << line;
    }
    if (rows_.size() < framesEnded_) s << "(the last " << rows_.size() << " of " << framesEnded_ << " frames)\n";
    return s.str();
}

}  // namespace engine
