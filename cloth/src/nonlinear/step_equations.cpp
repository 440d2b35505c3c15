#include "step_equations.h"

#include <algorithm>

#include "cloth/forces.h"

namespace cloth {

void stagePositions(const StepEquations& eq, State& at) {
    at.x = eq.xHat + eq.k * at.v;
    for (const auto& [i, x] : eq.pinX) at.x.col(i) = x;
}

void stepForces(const StepEquations& eq, const State& at, Points& f, ThreadPool* pool, AirWorkspace* workspace) {
    computeForces(eq.model, eq.env, at, eq.input.externalForce, f);
    if (eq.input.air) {
        addAirForces(eq.model, at, *eq.input.air, f, nullptr, pool, workspace);
    } else if (eq.input.damping && eq.vStart) {
        for (Index i = 0; i < eq.model.particleCount(); ++i)
            f.col(i) -= (*eq.input.damping)[i] * (at.v.col(i) - eq.vStart->col(i));
    }
}

Scalar stepResidual(const StepEquations& eq, const State& at, const Points& f, const std::vector<std::uint8_t>& pinned,
                    Points& residual) {
    const auto& mass = eq.model.masses();
    residual.resize(3, eq.model.particleCount());
    Scalar worst = 0;
    for (Index i = 0; i < eq.model.particleCount(); ++i) {
        if (pinned[i]) {
            residual.col(i).setZero();
            continue;
        }
        residual.col(i) = mass[i] * (at.v.col(i) - eq.vHat.col(i)) - eq.k * f.col(i);
        worst = std::max(worst, residual.col(i).cwiseAbs().maxCoeff() / mass[i]);
    }
    return worst;
}

void springStiffnessTimes(const Model& model, const Points& x, bool compressionRule, const Points& in, Points& out) {
    out.setZero(3, model.particleCount());
    for (const Spring& s : model.springs()) {
        const Vec3 d = springJacobian(x.col(s.i), x.col(s.j), s.k, s.rest, compressionRule) * (in.col(s.j) - in.col(s.i));
        out.col(s.i) += d;
        out.col(s.j) -= d;
    }
}

}  // namespace cloth
