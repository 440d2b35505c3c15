#pragma once
// The external force a study peer (a solver of another library: bullet_kind.cpp,
// nvidia_newton_kind.cpp) gets at each step: the air the library evaluated for the step (none:
// zero) less the environment's linear drag, -drag m v. Gravity is the peer's own.

#include "cloth/forces.h"
#include "cloth/model.h"
#include "cloth/system.h"

namespace study {

inline void peerForce(const cloth::Model& m, const cloth::Environment& env, const cloth::State& state,
                      const cloth::StepInput& input, cloth::Points& out) {
    out = input.externalForce ? *input.externalForce : cloth::Points::Zero(3, m.particleCount());
    for (cloth::Index i = 0; i < m.particleCount(); ++i) out.col(i) -= env.drag * m.masses()[i] * state.v.col(i);
}

}  // namespace study
