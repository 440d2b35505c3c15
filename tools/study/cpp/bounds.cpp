#include "bounds.h"

namespace study {

std::string missedBounds(const ExtremeRun& run, const ExtremeRun& reference, const Extreme& x) {
    if (!run.stable) return "unstable";
    std::string misses;
    auto miss = [&misses](const char* bound) {
        if (!misses.empty()) misses += ';';
        misses += bound;
    };
    if (!(run.p99Stretch <= kP99Factor * reference.p99Stretch + kP99Points)) miss("p99");
    if (!(run.peakStretch <= kPeakFactor * reference.peakStretch + kPeakPoints)) miss("peak");
    const double ratio = run.patchEnergyLate[0] / reference.patchEnergyLate[0];
    if (x.flutter && !(ratio >= kEnergyLow && ratio <= kEnergyHigh)) miss("energy");
    return misses;
}

}  // namespace study
