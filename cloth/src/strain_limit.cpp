#include "cloth/strain_limit.h"

#include <cmath>

namespace cloth {

int limitStretch(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                 Scalar h, State& state) {
    const auto& mass = model.masses();
    int corrections = 0;
    for (int pass = 0; pass < passes; ++pass) {
        int thisPass = 0;
        for (const Spring& s : model.springs()) {
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
            ++thisPass;
        }
        corrections += thisPass;
        if (thisPass == 0) break;
    }
    return corrections;
}

}  // namespace cloth
