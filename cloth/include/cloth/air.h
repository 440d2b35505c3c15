#pragma once
// Aerodynamic forces on the cloth's triangles from the air's velocity relative to each triangle
// (scene wind minus the triangle's own velocity). The paper does not model air; a flag on a
// moving vehicle only streams behind it because of these forces.
//
// Per triangle with area A, unit normal n, relative air velocity w = wind - (v_a + v_b + v_c)/3:
//   pressure drag  F_d = 1/2 rho A Cd |w| (w . n) n
//   skin friction  F_t = 1/2 rho A Cf |w| (w - (w . n) n)
//   lift           F_l = 1/2 rho A Cl |w|^2 cos(theta) sin(theta) l, l = unit part of n
//                  orthogonal to w, oriented with (w . n) (theta: angle between w and the plane)
// Each triangle's force is shared equally by its three corners.

#include "cloth/model.h"

namespace cloth {

struct AirParams {
    Vec3 wind = Vec3::Zero();  // m/s, world frame
    Scalar density = 1.2;      // kg/m^3
    Scalar dragCoefficient = 1.0;
    Scalar liftCoefficient = 0.5;
    Scalar frictionCoefficient = 0.02;
};

// Adds the air forces to f (3 x n). Returns false (and adds nothing) when the params are all zero
// in effect (still air and a resting cloth are not skipped: call sites decide whether air is on).
void addAirForces(const Model& model, const State& state, const AirParams& air, Points& f);

}  // namespace cloth
