#pragma once
// Newton's method on the step's equations (step_equations.h), each iteration's linear system
//   (M - k df/dv - k^2 df/dx) dv = rhs
// solved by flexible GMRES (multigrid/gmres.h) preconditioned by the multigrid hierarchy of its
// symmetric part: the springs (with eq. 17 when compressionRule), the mass, the drag, and the
// symmetric positive part of the air's diagonal velocity blocks. The air's whole derivative
// (air.h's AirJacobian: position and velocity, non-symmetric, coupling each triangle's corners)
// enters the product.
//
// The first iteration linearizes the forces at the start of the step (x_n, v_n): for backward
// Euler that is the paper's system (Baraff & Witkin's step, eq. 17 under compression), with the
// air fully coupled. The later ones are Newton steps on R(v) with the exact derivative (eq. 17 in
// the preconditioner only: the exact matrix is indefinite where springs buckle, and without it a
// stiff flag that flutters converges slowly, by a factor near 1 per iteration), each with a backtracking line search on |R|_{M^-1}. The
// loop stops when the last iteration changed no particle's velocity by more than the tolerance
// (m/s), or after maxIterations. (A stop on |R_i| / m_i would ask far too much of stiff springs:
// a position error dx gives |R_i| / m_i = k h dx / m_i, 1e3 m/s for 1 cm at k = 1e4 N/m.)

#include <memory>
#include <vector>

#include "../multigrid/gmres.h"
#include "../multigrid/multigrid.h"
#include "../multigrid/reductions.h"
#include "cloth/air.h"
#include "compressed_springs.h"
#include "step_equations.h"

namespace cloth {

struct NewtonControl {
    int maxIterations = 8;
    double tolerance = 1e-3;        // m/s: the largest velocity change of the last iteration
    double linearTolerance = 1e-2;  // relative residual of each linear solve
    int maxLinearIterations = 60;
};

struct NewtonStats {
    int iterations = 0;        // Newton iterations (linear solves)
    int linearIterations = 0;  // GMRES iterations, all solves
    double residual = -1;      // max |R_i| / m_i at the end, m/s
    double correction = -1;    // the largest velocity change of the last iteration, m/s
};

class NewtonSolve {
public:
    explicit NewtonSolve(std::shared_ptr<ThreadPool> pool);
    ~NewtonSolve();
    // From `iterate` (positions x_n, velocities v_n with the pinned particles' set to their
    // targets'), solves the equations; iterate ends at (x(v), v). False when a value is not finite.
    bool solve(const StepEquations& eq, const NewtonControl& control, State& iterate, NewtonStats& stats);

private:
    void linearize(const StepEquations& eq, const State& at, bool exact);
    int solveLinear(const StepEquations& eq, const NewtonControl& control, const Points& rhs, Points& delta);
    void product(const StepEquations& eq, const std::vector<double>& x, std::vector<double>& y);
    Scalar evaluate(const StepEquations& eq, const State& at);
    bool lineSearch(const StepEquations& eq, const Points& delta, State& iterate, Scalar& merit, NewtonStats& stats);

    std::shared_ptr<ThreadPool> pool_;
    Reductions sums_;
    Multigrid<double> multigrid_;
    FlexibleGmres gmres_;
    AirJacobian air_;
    AirWorkspace airWorkspace_;
    std::vector<Mat3> airDiagonal_, airDamping_;
    std::vector<std::uint8_t> pinned_;
    CompressedSprings compressed_;
    Points force_, residual_, trialForce_, trialResidual_;
    std::vector<double> b_, x_, parts_;  // parts_: the air's rows of a product
};

}  // namespace cloth
