#pragma once
// Aerodynamic forces on the cloth's triangles from the air's velocity relative to each triangle
// (scene wind minus the triangle's own velocity). The paper does not model air; a flag on a
// moving vehicle only streams behind it because of these forces.
//
// Per triangle with area A, unit normal n (oriented so that w . n >= 0), relative air velocity
// w = wind - (v_a + v_b + v_c)/3, s = |w|, wn = w . n, c_X = 1/2 rho A C_X:
//   pressure drag  F_d = c_d s wn n
//   skin friction  F_t = c_f s (w - wn n)
//   lift           F_l = c_l |w|^2 cos(theta) sin(theta) l = c_l (wn s n - (wn^2 / s) w)
//                  (theta: angle between w and the plane; l: unit part of n orthogonal to w)
// Each triangle's force is shared equally by its three corners.
//
// Implicit air: backward Euler needs -df/dv. Its diagonal blocks are
//   C_i = -df_i/dv_i = sum over the triangles of i of (1/9) dF/dw
// (f_i = F/3 and dw/dv_i = -I/3). dF/dw is not symmetric (the terms from d|w| and d(w.n)), so
// what enters the system matrix W = M + h C + h^2 K is the symmetric positive semi-definite part
// of C_i (symmetric part, negative eigenvalues clamped to zero): W stays symmetric positive
// definite for Cholesky, CG and multigrid, and the air can only damp, never excite.

#include <array>
#include <vector>

#include "cloth/model.h"
#include "cloth/thread_pool.h"

namespace cloth {

struct AirParams {
    Vec3 wind = Vec3::Zero();  // m/s, world frame
    Scalar density = 1.2;      // kg/m^3
    Scalar dragCoefficient = 1.0;
    Scalar liftCoefficient = 0.5;
    Scalar frictionCoefficient = 0.02;
};

// Adds the air forces to f (3 x n). With velocityJacobian non-null, also sets
// (*velocityJacobian)[i] = df_i/dv_i (the exact diagonal blocks of the force's velocity
// derivative, resized to n).
// The work is split among `pool`'s threads when given (the same bits for any count).
// `workspace`: the per-triangle arrays reused from call to call, owned by the caller (null: fresh ones).
struct AirWorkspace {
    std::vector<Scalar> shareX, shareY, shareZ;
    std::vector<Mat3> blocks;
};
void addAirForces(const Model& model, const State& state, const AirParams& air, Points& f,
                  std::vector<Mat3>* velocityJacobian = nullptr, ThreadPool* pool = nullptr,
                  AirWorkspace* workspace = nullptr);

// The part of -dfdv that enters W: the symmetric part of -dfdv with its negative eigenvalues
// clamped to zero (in closed form, from its smallest eigenvalue).
Mat3 dampingBlock(const Mat3& dfdv);
// The smallest eigenvalue of a symmetric 3x3, in closed form.
Scalar smallestEigenvalue(const Mat3& symmetric);

// -df_i/dv_i of the air for every particle, as dampingBlock()s: what StepInput::damping takes.
// Split among `pool`'s threads when given (each block alone: the same bits).
void airDamping(const std::vector<Mat3>& velocityJacobian, std::vector<Mat3>& damping, ThreadPool* pool = nullptr);

// The air force's whole derivative at one state, for a step that couples the air fully
// (newton): df/dx, through each triangle's normal and area, and df/dv, through the relative air.
// A triangle's force F(w, N) depends on the mean velocity of its corners and on N = (b-a)x(c-a),
// so it couples its three corners, and neither part is symmetric. Kept per triangle as dF/dw and
// dF/dN (3 x 3 each): a product is one pass over the triangles and one over the particles, in the
// order addAirForces sums (the same bits for any thread count).
class AirJacobian {
public:
    // Each pass below is split among `pool`'s threads when given: a triangle's or a particle's
    // work is done alone, so the bits do not depend on the thread count.
    void compute(const Model& model, const State& state, const AirParams& air, ThreadPool* pool = nullptr);
    // out += (positionScale df/dx + velocityScale df/dv) in, all 3n particle-major.
    void apply(const Model& model, const double* in, Scalar positionScale, Scalar velocityScale, double* out) const;
    // apply() in two parts, for a caller that splits the second among threads of its own: each
    // triangle's part of the product, then out += the sums of those parts for particles
    // [begin, end).
    void triangleParts(const Model& model, const double* in, Scalar positionScale, Scalar velocityScale,
                       ThreadPool* pool = nullptr) const;
    void addParts(const Model& model, int begin, int end, double* out) const;
    // df_i/dv_i: the diagonal blocks of df/dv (addAirForces' velocityJacobian).
    void velocityDiagonal(const Model& model, std::vector<Mat3>& out, ThreadPool* pool = nullptr) const;

private:
    // Per triangle, as structures of arrays so that a product takes a pack of triangles at once:
    // dF/dw and dF/dN by row-major entry (zero for a degenerate triangle or still air), e1 = b - a
    // and e2 = c - a by coordinate. Scratch, 3 and 9 per triangle: each corner's part of a
    // product, and dF/dw / 9 for the diagonal blocks.
    std::array<std::vector<Scalar>, 9> dFdw_, dFdN_;
    std::array<std::vector<Scalar>, 3> e1_, e2_;
    mutable std::vector<Scalar> share_, ninth_;
};

}  // namespace cloth
