#include "small_steps/stable_step.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cloth {

Scalar springFrequencyBound(const Model& model) {
    std::vector<Scalar> sum(std::size_t(model.particleCount()), 0);
    for (const Spring& s : model.springs()) sum[std::size_t(s.i)] += s.k, sum[std::size_t(s.j)] += s.k;
    Scalar w2 = 0;
    for (Index i = 0; i < model.particleCount(); ++i) w2 = std::max(w2, 2 * sum[std::size_t(i)] / model.masses()[i]);
    return std::sqrt(w2);
}

Scalar airRateBound(const Model& model, const State& state, const AirParams* air) {
    if (!air) return 0;
    const Scalar k = air->density / 4 *
                     (2 * std::abs(air->dragCoefficient) + 3 * std::abs(air->frictionCoefficient) +
                      4 * std::abs(air->liftCoefficient)) / 9;
    std::vector<Scalar> rate(std::size_t(model.particleCount()), 0);
    for (const Triangle& t : model.triangles()) {
        const Vec3 a = state.x.col(t[0]), N = (state.x.col(t[1]) - a).cross(state.x.col(t[2]) - a);
        const Vec3 w = air->wind - (state.v.col(t[0]) + state.v.col(t[1]) + state.v.col(t[2])) / 3;
        for (const Index i : t) rate[std::size_t(i)] += k * N.norm() * w.norm();
    }
    Scalar c = 0;
    for (Index i = 0; i < model.particleCount(); ++i) c = std::max(c, rate[std::size_t(i)] / model.masses()[i]);
    return c;
}

int stableSubsteps(Scalar h, Scalar springFrequency, Scalar airRate, Scalar fraction) {
    const Scalar bound = 2 / std::max(springFrequency + airRate, Scalar(1e-12));
    const Scalar substeps = std::ceil(h / (fraction * bound));
    return int(std::clamp(substeps, Scalar(1), Scalar(100000)));
}

Scalar largestMove(const std::vector<Vec3>& start, const std::vector<Vec3>& end, const State& state,
                   const Vec3& frame, Scalar h) {
    Scalar move = 0;
    for (std::size_t k = 0; k < start.size() && k < end.size(); ++k) move = std::max(move, (end[k] - start[k]).norm());
    Scalar speed2 = 0;
    for (Index i = 0; i < state.v.cols(); ++i) speed2 = std::max(speed2, (state.v.col(i) - frame).squaredNorm());
    return std::max(move, std::sqrt(speed2) * h);
}

int pacedSubsteps(Scalar move, Scalar maxMove) {
    if (maxMove <= 0) return 0;
    // A move of exactly n pieces takes n substeps, not n + 1 by a rounding error.
    return int(std::clamp(std::ceil(move / maxMove - 1e-9), Scalar(0), Scalar(100000)));
}

}  // namespace cloth
