#include "krylov.h"

namespace cloth {

template <class T>
int ConjugateGradients<T>::solve(const KrylovSystem<T>& system, const KrylovControl& control, std::vector<T>& x,
                                 std::vector<T>& r, double& rel) {
    int iterations = 0;
    double rz = 0, alpha = 0;
    while (iterations < control.maxIterations && (!control.adaptive || !system.converged(rel, r, x))) {
        system.precondition(r, z_);
        ++iterations;
        const double rzNext = sums_.dot(r, z_);
        if (iterations == 1) {
            p_ = z_;
        } else {
            // flexible: z.(r - r_last) / rz, with r - r_last = -alpha W p_last (in q)
            const T beta = T(control.flexible ? -alpha * sums_.dot(z_, q_) / rz : rzNext / rz);
            for (std::size_t k = 0; k < p_.size(); ++k) p_[k] = z_[k] + beta * p_[k];
        }
        rz = rzNext;
        system.apply(p_, q_);  // q = W p
        const double pq = sums_.dot(p_, q_);
        if (!(pq > 0)) break;  // W p = 0 only for p = 0: converged to rounding
        alpha = rz / pq;
        const T a = T(alpha);
        for (std::size_t k = 0; k < x.size(); ++k) x[k] += a * p_[k], r[k] -= a * q_[k];
        if (control.adaptive) rel = sums_.norm(r) / control.bNorm;
    }
    return iterations;
}

template class ConjugateGradients<float>;
template class ConjugateGradients<double>;

}  // namespace cloth
