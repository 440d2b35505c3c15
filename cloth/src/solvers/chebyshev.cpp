#include "cloth/solvers/chebyshev_settings.h"
#include "cloth/solver_kind.h"
#include "solvers/step_common.h"

#include "cloth/paper_step.h"
#include "cloth/diagnostics.h"

namespace cloth {

namespace {


// Jacobi with Chebyshev semi-iterative acceleration (H. Wang, "A Chebyshev Semi-Iterative
// Approach for Accelerating Projective and Position-based Dynamics", SIGGRAPH Asia 2015):
//   x(k+1) = w(k+1) (J(x(k)) - x(k-1)) + x(k-1),  w1 = 1, w2 = 2 / (2 - rho^2),
//   w(k+1) = 4 / (4 - rho^2 w(k)),
// where J is one Jacobi sweep and rho the spectral radius of the Jacobi iteration. Each iteration
// costs one sweep, like the paper's; rho is estimated from the system unless given: for springs
// along a line, h^2 sum_j k_ij / (m_i + h^2 sum_j k_ij) is the scalar Jacobi radius bound.
class ChebyshevSolver final : public ImplicitSolver {
    Points prev_, next_;

    bool solve(const Model& model, StepResult& result) override {
        const ChebyshevSettings& opt = settings<ChebyshevSettings>();
        Scalar rho = opt.rho;
        if (rho <= 0) {
            const Scalar h2 = sys_.h * sys_.h;
            std::vector<Scalar> ksum(model.particleCount(), 0);
            for (const Spring& s : model.springs()) ksum[s.i] += s.k, ksum[s.j] += s.k;
            for (Index i = 0; i < model.particleCount(); ++i)
                if (!sys_.pinned[i]) rho = std::max(rho, h2 * ksum[i] / (model.masses()[i] + h2 * ksum[i]));
            rho = std::min(rho, Scalar(0.9999));
        }
        jacobiStart(sys_, dv_);
        prev_ = dv_;
        Scalar omega = 1;
        for (int k = 1; k <= opt.iterations; ++k) {
            jacobiSweep(model, sys_, dv_, next_);
            omega = k == 1 ? 1 : (k == 2 ? 2 / (2 - rho * rho) : 4 / (4 - rho * rho * omega));
            next_ = omega * (next_ - prev_) + prev_;  // pinned rows: prescribed in both, unchanged
            std::swap(prev_, dv_);
            std::swap(dv_, next_);
        }
        result.iterations = opt.iterations;
        return true;
    }
};

}  // namespace

FLAGSIM_SOLVER_KIND(chebyshev) {
    using C = ChebyshevSettings;
    using key = SolverKeys;
    return {"chebyshev", "Jacobi with Chebyshev semi-iterative acceleration (Wang 2015)", defaultsTo<C>,
            withCommon({key::shown(key::integer("iterations", &C::iterations, 0, 100000,
                                                "accelerated Jacobi sweeps after dv(0)")),
                        key::real("rho", &C::rho, 0, 1, false, true, "Jacobi spectral radius; 0 = estimated each step")},
                       true),
            {},
            createSolver<ChebyshevSolver>};
}

}  // namespace cloth
