#pragma once
// The small_steps solver's float kernels on the stencil layout (stencil_cloth.h), each a loop over
// a range of slots [begin, end) that vectorizes with no gathers (contiguous loads at constant
// offsets). One substep is springs + air (each slot's own), then integrate (each particle's sum
// of them): a range's integrate reads slots of the neighbouring ranges, so threads meet between
// the two.

#include "small_steps/stencil_cloth.h"

namespace cloth {

// The force of family f's spring at each slot on its lower end (eq. 15):
// k (L - l0) / L (x[p + d] - x[p]), zero for a slot with no spring or a spring of no length.
void springKernel(const StencilCloth& cloth, int f, StencilState& s, int begin, int end);

struct AirConstants {
    float windX = 0, windY = 0, windZ = 0;
    float scale = 0;  // rho / 4 / 3: a corner's third of each triangle's force
    float normal = 0, friction = 0, lift = 0;  // c_d - c_f + c_l, c_f, c_l (air.h)
};

// Each quad's two triangles' air force (air.h's formula, as addAirForces writes it), a third to
// each corner, summed per corner of the quad; zero for a slot that is not a quad.
void airKernel(const StencilCloth& cloth, const AirConstants& air, StencilState& s, int begin, int end);

struct IntegrateConstants {
    float h = 0;                     // the substep
    float gx = 0, gy = -9.81f, gz = 0;
    float drag = 0;                  // -drag m v
    bool air = false;                // add the quads' air
    const float* pinned = nullptr;   // 1 for a pinned particle, else 0
    const float *pinX = nullptr, *pinY = nullptr, *pinZ = nullptr;     // its position at the substep's end
    const float *pinVX = nullptr, *pinVY = nullptr, *pinVZ = nullptr;  // and its velocity
    const float *extX = nullptr, *extY = nullptr, *extZ = nullptr;     // a constant external force, or null
};

// Symplectic Euler for each particle of [begin, end): f = m (g - drag v) + the springs' forces
// (+F at its lower end's slot, -F at the upper's) + the air + the external force; v += h f / m,
// x += h v. A pinned particle moves to its target with its velocity.
void integrateKernel(const StencilCloth& cloth, const IntegrateConstants& c, StencilState& s, int begin, int end);

// The largest |v - pole|^2 of the particles of [begin, end) of the velocities (vx, vy, vz), 0 for
// none, a NaN skipped as std::max skips it: a maximum, exact in any order, kept per lane and then
// over the lanes.
float fastestSquaredKernel(const float* vx, const float* vy, const float* vz, const float pole[3], int begin, int end);

}  // namespace cloth
