#include "cloth/forces.h"

#include "cloth/system.h"

namespace cloth {

void computeForces(const Model& model, const Environment& env, const State& state,
                   const Points* externalForce, Points& f) {
    const Index n = model.particleCount();
    const auto& mass = model.masses();
    f.resize(3, n);
    for (Index i = 0; i < n; ++i) f.col(i) = mass[i] * (env.gravity - env.drag * state.v.col(i));
    if (externalForce) f += *externalForce;
    for (const Spring& s : model.springs()) {
        const Vec3 fi = springForce(state.x.col(s.i), state.x.col(s.j), s.k, s.rest);
        f.col(s.i) += fi;
        f.col(s.j) -= fi;
    }
}

}  // namespace cloth
