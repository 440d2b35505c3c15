#include "engine/profiler.h"

#include "engine/atomic_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace engine {

int Profiler::addPhase(const std::string& name) {
    const int existing = phaseId(name);
    if (existing >= 0) return existing;
    names_.push_back(name);
    current_.push_back(0);
    return static_cast<int>(names_.size()) - 1;
}

int Profiler::phaseId(const std::string& name) const {
    const auto it = std::find(names_.begin(), names_.end(), name);
    return it == names_.end() ? -1 : static_cast<int>(it - names_.begin());
}

void Profiler::setTrace(Trace* trace) {
    trace_ = trace;
    traceNames_.clear();
    traceFrameName_ = trace ? trace->nameId("frame") : -1;
}

void Profiler::tracePhase(int phase, Clock::time_point t0, Clock::time_point t1) {
    if (traceNames_.size() < names_.size()) traceNames_.resize(names_.size(), -1);
    if (traceNames_[phase] < 0) traceNames_[phase] = trace_->nameId(names_[phase]);
    trace_->complete(traceNames_[phase], Trace::Category::Phase, t0, t1);
}

void Profiler::beginFrame() {
    std::fill(current_.begin(), current_.end(), 0.0);
    frameStart_ = Clock::now();
}

void Profiler::endFrame() {
    const Clock::time_point end = Clock::now();
    std::vector<double> row = current_;
    row.push_back(ms(end - frameStart_));
    if (trace_)
        trace_->complete(traceFrameName_, Trace::Category::Frame, frameStart_, end, static_cast<int>(rows_.size()));
    rows_.push_back(std::move(row));
}

// Only the second level of Bullet's zones is kept as columns: the first
// (internalSingleStepSimulation) is the whole tick, which the "bullet" phase already times, and
// deeper levels repeat their parents. A trace gets every level, named by Bullet.
void Profiler::enterZone(const char* name) {
    const int phase = zones_.size() == 1 ? addPhase(std::string("bullet:") + name) : -1;
    zones_.push_back({phase, Clock::now(), name});
}

void Profiler::leaveZone() {
    if (zones_.empty()) return;
    const OpenZone& z = zones_.back();
    if (z.phase >= 0 || trace_) {  // a deeper zone only ends an event of a trace
        const Clock::time_point end = Clock::now();
        if (z.phase >= 0) add(z.phase, ms(end - z.t0));
        if (trace_) trace_->complete(trace_->staticNameId(z.name), Trace::Category::Zone, z.t0, end);
    }
    zones_.pop_back();
}

std::vector<std::string> Profiler::columns() const {
    std::vector<std::string> c = names_;
    c.push_back("frame");
    return c;
}

std::vector<Profiler::Stats> Profiler::summary() const {
    const std::size_t cols = names_.size() + 1;
    std::vector<Stats> out(cols);
    if (rows_.empty()) return out;
    std::vector<double> v;
    for (std::size_t c = 0; c < cols; ++c) {
        v.clear();
        // A phase registered mid-run (a Bullet zone) is zero in the rows before it.
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
    for (std::size_t f = 0; f < rows_.size(); ++f) {
        out << f;
        const auto& row = rows_[f];
        for (std::size_t c = 0; c < names_.size(); ++c) {
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
    return s.str();
}

}  // namespace engine
