#include "cloth/forces.h"

#include "spring_terms.h"

namespace cloth {

Vec3 springForce(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest) {
    const SpringTerms<Scalar> t = springTerms(xi, xj, k, rest, false);
    return t.fm * Vec3(t.ux, t.uy, t.uz);
}

Mat3 springJacobian(const Vec3& xi, const Vec3& xj, Scalar k, Scalar rest, bool compressionRule) {
    const SpringTerms<Scalar> t = springTerms(xi, xj, k, rest, compressionRule);
    const Vec3 u(t.ux, t.uy, t.uz);
    return t.a * Mat3::Identity() + t.b * (u * u.transpose());
}

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
