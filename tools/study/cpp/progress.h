#pragma once
// The study's progress: rows done out of rows planned, the row at work, the time so far and an
// estimate of the time left. On a terminal one line updated in place; otherwise (a log, CI) a
// plain line per finished row, the last one saying that all rows are done.

#include <chrono>
#include <cstdio>
#include <string>

namespace study {

class Progress {
public:
    using Clock = std::chrono::steady_clock;
    // `planned` rows in all; `terminal`: update one line in place.
    Progress(long planned, bool terminal, std::FILE* out = stderr);
    // The row (or group of rows) now at work, shown on a terminal's line.
    void begin(const std::string& what);
    // `rows` more rows done: `what` they were, with a note (what was reused, how long it took).
    void done(long rows, const std::string& what, const std::string& note = {});
    // The last line: every row done, in how long, with a closing note.
    void finish(const std::string& note = {});
    long planned() const { return planned_; }
    long finished() const { return done_; }

private:
    std::string status() const;  // "[12/48] 25%, 1m02s, about 3m10s left"
    long planned_, done_ = 0;
    bool terminal_;
    std::FILE* out_;
    Clock::time_point start_ = Clock::now();
};

// A duration as "42s", "3m05s" or "1h02m".
std::string clockText(double seconds);

}  // namespace study
