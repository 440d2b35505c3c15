#include "cloth/diagnostics.h"

#include <algorithm>
#include <cmath>

#include "cloth/forces.h"
#include "cloth/paper_step.h"
#include "cloth/exact_solve.h"

namespace cloth {

namespace {

// The value below which 99% of the samples lie (nearest rank), and the maximum.
void maxAndP99(std::vector<Scalar>& values, Scalar& maxOut, Scalar& p99Out) {
    if (values.empty()) {
        maxOut = p99Out = 0;
        return;
    }
    const std::size_t rank = static_cast<std::size_t>(std::ceil(0.99 * values.size())) - 1;
    std::nth_element(values.begin(), values.begin() + rank, values.end());
    p99Out = values[rank];
    maxOut = *std::max_element(values.begin() + rank, values.end());
}

}  // namespace

Index firstNonFinite(const State& state) {
    // The common case in one vectorizable pass: x * 0 is 0 for a finite x and NaN otherwise, and
    // a NaN stays in a sum (eight independent sums, so the loop needs no reassociation to vectorize).
    auto anyNonFinite = [](const Points& p) {
        const Scalar* d = p.data();
        const Index n = p.size();
        Scalar acc[8] = {};
        Index k = 0;
        for (; k + 8 <= n; k += 8)
            for (int l = 0; l < 8; ++l) acc[l] += d[k + l] * Scalar(0);
        for (; k < n; ++k) acc[0] += d[k] * Scalar(0);
        Scalar sum = 0;
        for (Scalar a : acc) sum += a;
        return sum != 0;
    };
    if (!anyNonFinite(state.x) && !anyNonFinite(state.v)) return -1;
    for (Index i = 0; i < static_cast<Index>(state.x.cols()); ++i)
        if (!state.x.col(i).allFinite() || !state.v.col(i).allFinite()) return i;
    return -1;
}

Diagnostics measure(const Model& model, const Environment& env, const State& state,
                    bool structuralOnly) {
    Diagnostics d;
    d.finite = firstNonFinite(state) < 0;
    std::vector<Scalar> stretch, compression;
    stretch.reserve(model.springCount());
    compression.reserve(model.springCount());
    for (const Spring& s : model.springs()) {
        d.potential += springEnergy(state.x.col(s.i), state.x.col(s.j), s.k, s.rest);
        if (structuralOnly && s.kind != SpringKind::Structural) continue;
        const Scalar strain = (state.x.col(s.j) - state.x.col(s.i)).norm() / s.rest - 1;
        stretch.push_back(std::max(strain, Scalar(0)));
        compression.push_back(std::max(-strain, Scalar(0)));
    }
    maxAndP99(stretch, d.maxStretch, d.p99Stretch);
    maxAndP99(compression, d.maxCompression, d.p99Compression);
    const auto& mass = model.masses();
    for (Index i = 0; i < model.particleCount(); ++i) {
        d.kinetic += 0.5 * mass[i] * state.v.col(i).squaredNorm();
        d.potential -= mass[i] * env.gravity.dot(state.x.col(i));
    }
    return d;
}

Scalar solveError(const StepProblem& problem, const Points& dv) {
    LinearSystem sys;
    buildSystem(problem, sys);
    const Model& model = problem.model;
    Points exact;
    if (!solveExact(model, sys, exact)) return std::numeric_limits<Scalar>::quiet_NaN();
    const Scalar ref = exact.norm();
    return ref > 0 ? (dv - exact).norm() / ref : (dv - exact).norm();
}

}  // namespace cloth

namespace cloth {

const char* instability(const Diagnostics& d, const State& state, const Vec3& anchor,
                        const StabilityLimits& limits) {
    if (!d.finite) return "non-finite state";
    if (d.maxStretch > limits.maxStretch) return "stretch beyond limit";
    for (Index i = 0; i < static_cast<Index>(state.x.cols()); ++i) {
        if ((state.x.col(i) - anchor).norm() > limits.maxDistance) return "position beyond limit";
        if (state.v.col(i).norm() > limits.maxSpeed) return "speed beyond limit";
    }
    return nullptr;
}

}  // namespace cloth
