#include "progress.h"

#include <cmath>

namespace study {

std::string clockText(double seconds) {
    const long s = std::lround(std::max(0.0, seconds));
    char b[32];
    if (s < 60) std::snprintf(b, sizeof b, "%lds", s);
    else if (s < 3600) std::snprintf(b, sizeof b, "%ldm%02lds", s / 60, s % 60);
    else std::snprintf(b, sizeof b, "%ldh%02ldm", s / 3600, s / 60 % 60);
    return b;
}

Progress::Progress(long planned, bool terminal, std::FILE* out) : planned_(planned), terminal_(terminal), out_(out) {}

std::string Progress::status() const {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const long percent = planned_ > 0 ? 100 * done_ / planned_ : 100;
    char b[120];
    std::snprintf(b, sizeof b, "[%ld/%ld] %ld%%, %s", done_, planned_, percent, clockText(elapsed).c_str());
    std::string s = b;
    if (done_ > 0 && done_ < planned_)
        s += ", about " + clockText(elapsed / double(done_) * double(planned_ - done_)) + " left";
    return s;
}

void Progress::begin(const std::string& what) {
    if (!terminal_) return;
    std::fprintf(out_, "\r\033[K%s  %s ...", status().c_str(), what.c_str());
    std::fflush(out_);
}

void Progress::done(long rows, const std::string& what, const std::string& note) {
    done_ += rows;
    const std::string tail = note.empty() ? "" : " (" + note + ")";
    if (terminal_) std::fprintf(out_, "\r\033[K%s  %s%s", status().c_str(), what.c_str(), tail.c_str());
    else std::fprintf(out_, "%s  %s%s\n", status().c_str(), what.c_str(), tail.c_str());
    std::fflush(out_);
}

void Progress::finish(const std::string& note) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    std::fprintf(out_, "%s[%ld/%ld] all %ld rows done in %s%s\n", terminal_ ? "\r\033[K" : "", done_, planned_, done_,
                 clockText(elapsed).c_str(), note.empty() ? "" : ("; " + note).c_str());
    std::fflush(out_);
}

}  // namespace study
