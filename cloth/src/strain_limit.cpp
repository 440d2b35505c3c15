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
            const Scalar L = d.norm(), limit = (1 + maxStretch) * s.rest;
            if (L <= limit || L < Scalar(1e-12)) continue;
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
