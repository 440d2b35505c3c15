#include "cloth/strain_limit.h"

#include <cmath>
#include <cstdint>

namespace cloth {

int limitStretch(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                 Scalar h, State& state) {
    const auto& mass = model.masses();
    const auto& springs = model.springs();
    const std::int64_t count = static_cast<std::int64_t>(springs.size());
    // A spring found within its limit stays so until one of its ends moves. movedAt[p] is the
    // stamp of particle p's last correction (stamp = pass * count + spring + 1; 0: never), so from
    // the second pass on a spring whose ends have not moved since its check one pass earlier is
    // skipped. The result is bit-identical to checking every spring: only checks that would find
    // nothing are left out. (A spring corrected at its own stamp is checked again.)
    std::vector<std::int64_t> movedAt(static_cast<std::size_t>(model.particleCount()), 0);
    int corrections = 0;
    for (int pass = 0; pass < passes; ++pass) {
        int thisPass = 0;
        for (std::int64_t k = 0; k < count; ++k) {
            const Spring& s = springs[static_cast<std::size_t>(k)];
            const std::int64_t stamp = pass * count + k + 1;
            if (pass > 0 && movedAt[s.i] < stamp - count && movedAt[s.j] < stamp - count) continue;
            const Vec3 d = state.x.col(s.j) - state.x.col(s.i);
            // Most springs are within the limit: decide on squared lengths, without a square root
            // (a spring over by a rounding error of the square may be skipped: a correction of ulps).
            const Scalar limit = (1 + maxStretch) * s.rest, L2 = d.squaredNorm();
            if (L2 <= limit * limit || L2 < Scalar(1e-24)) continue;
            const Scalar L = std::sqrt(L2);
            if (L <= limit) continue;
            const Scalar wi = pinned[s.i] ? 0 : 1 / mass[s.i], wj = pinned[s.j] ? 0 : 1 / mass[s.j];
            if (wi + wj == 0) continue;
            const Vec3 corr = (L - limit) / (L * (wi + wj)) * d;  // total shortening, split by 1/m
            state.x.col(s.i) += wi * corr;
            state.x.col(s.j) -= wj * corr;
            state.v.col(s.i) += (wi / h) * corr;
            state.v.col(s.j) -= (wj / h) * corr;
            movedAt[s.i] = movedAt[s.j] = stamp;
            ++thisPass;
        }
        corrections += thisPass;
        if (thisPass == 0) break;
    }
    return corrections;
}

}  // namespace cloth
