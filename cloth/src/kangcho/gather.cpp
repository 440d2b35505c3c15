#include "kangcho/gather.h"

#include <chrono>
#include <cmath>

#include "kernels.h"

namespace cloth {

template <class T>
void GatherKangCho<T>::prepare(const Model& model) {
    modelId_ = model.id();
    n_ = model.particleCount();
    springs_ = model.springCount();
    adjStart_.assign(model.adjStart().begin(), model.adjStart().end());
    adjSpring_.assign(model.adjSpring().begin(), model.adjSpring().end());
    adjOther_.assign(model.adjOther().begin(), model.adjOther().end());
    adjSign_.resize(adjSpring_.size());
    const auto& sp = model.springs();
    for (int p = 0; p < n_; ++p)
        for (int e = adjStart_[p]; e < adjStart_[p + 1]; ++e) adjSign_[e] = sp[adjSpring_[e]].i == p ? T(1) : T(-1);
    si_.resize(springs_);
    sj_.resize(springs_);
    k_.resize(springs_);
    rest_.resize(springs_);
    for (int s = 0; s < springs_; ++s) {
        si_[s] = sp[s].i;
        sj_[s] = sp[s].j;
        k_[s] = T(sp[s].k);
        rest_[s] = T(sp[s].rest);
    }
    mass_.assign(model.masses().begin(), model.masses().end());
    for (auto* v : {&rhs_, &dvA_, &dvB_, &pin_}) v->resize(3 * std::size_t(n_));
    winv_.resize(6 * std::size_t(n_));
    for (auto* v : {&ux_, &uy_, &uz_, &a_, &b_, &fm_}) v->resize(springs_);
    pinned_.resize(n_);
}

// Marks the pinned particles and stores their velocity changes.
template <class T>
void GatherKangCho<T>::setPins(const State& state, const StepInput& input) {
    gatherPins(state, input, pinned_, pin_);
}

// Computes every spring's direction, Jacobian terms and force magnitude.
template <class T>
void GatherKangCho<T>::computeSprings(const State& state, bool compressionRule) {
    const double* xs = state.x.data();
    // Springs: u, the Jacobian's a and b (eqs. 16, 17) and the force magnitude (eq. 15).
    pool_.run(springs_, [&](int begin, int end) {
        for (int s = begin; s < end; ++s) {
            const int i = si_[s], j = sj_[s];
            const SpringTerms<T> t = springTerms(T(xs[3 * j] - xs[3 * i]), T(xs[3 * j + 1] - xs[3 * i + 1]),
                                                 T(xs[3 * j + 2] - xs[3 * i + 2]), k_[s], rest_[s], compressionRule);
            ux_[s] = t.ux, uy_[s] = t.uy, uz_[s] = t.uz, a_[s] = t.a, b_[s] = t.b, fm_[s] = t.fm;
        }
    });
}

// Assembles every particle's right-hand side and inverse diagonal block, and the first guess.
template <class T>
void GatherKangCho<T>::assembleParticles(const Environment& env, const State& state, const StepInput& input) {
    const T h = T(input.h), h2 = h * h, c = T(env.drag);
    const T g[3] = {T(env.gravity.x()), T(env.gravity.y()), T(env.gravity.z())};
    const double* vs = state.v.data();
    const double* ext = input.externalForce ? input.externalForce->data() : nullptr;
    const std::vector<Mat3>* damping = input.damping;
    // Particles: f, W_ii (eq. 12), b_i (eq. 7 with pinned columns), W_ii^-1 and dv(0) (eq. 11).
    pool_.run(n_, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            T* r = &rhs_[3 * i];
            T* d = &dvA_[3 * i];
            T* w = &winv_[6 * i];
            if (pinned_[i]) {
                for (int a = 0; a < 3; ++a) r[a] = d[a] = pin_[3 * i + a];
                w[0] = w[3] = w[5] = T(1);
                w[1] = w[2] = w[4] = T(0);
                continue;
            }
            const T m = mass_[i];
            const T vi[3] = {T(vs[3 * i]), T(vs[3 * i + 1]), T(vs[3 * i + 2])};
            T f[3], jv[3] = {0, 0, 0};
            for (int a = 0; a < 3; ++a) f[a] = m * (g[a] - c * vi[a]) + (ext ? T(ext[3 * i + a]) : T(0));
            T A = 0, Bxx = 0, Bxy = 0, Bxz = 0, Byy = 0, Byz = 0, Bzz = 0;
            for (int e = adjStart_[i]; e < adjStart_[i + 1]; ++e) {
                const int s = adjSpring_[e], j = adjOther_[e];
                const T ux = ux_[s], uy = uy_[s], uz = uz_[s], as = a_[s], bs = b_[s];
                const T fs = adjSign_[e] * fm_[s];
                f[0] += fs * ux;
                f[1] += fs * uy;
                f[2] += fs * uz;
                A += as;
                Bxx += bs * ux * ux, Bxy += bs * ux * uy, Bxz += bs * ux * uz;
                Byy += bs * uy * uy, Byz += bs * uy * uz, Bzz += bs * uz * uz;
                // J (v_j - v_i + dv_j if j is pinned), J x = a x + b u (u . x)
                T q[3] = {T(vs[3 * j]) - vi[0], T(vs[3 * j + 1]) - vi[1], T(vs[3 * j + 2]) - vi[2]};
                if (pinned_[j]) q[0] += pin_[3 * j], q[1] += pin_[3 * j + 1], q[2] += pin_[3 * j + 2];
                const T uq = bs * (ux * q[0] + uy * q[1] + uz * q[2]);
                jv[0] += as * q[0] + uq * ux;
                jv[1] += as * q[1] + uq * uy;
                jv[2] += as * q[2] + uq * uz;
            }
            for (int a = 0; a < 3; ++a) r[a] = h * f[a] + h2 * jv[a];
            // W = m (1 + h c) I + h^2 (A I + B) (+ h C_i), as 6 numbers, and its inverse.
            const T diag = m * (T(1) + h * c) + h2 * A;
            T W[6] = {diag + h2 * Bxx, h2 * Bxy, h2 * Bxz, diag + h2 * Byy, h2 * Byz, diag + h2 * Bzz};
            if (damping) {  // + h C_i (implicit external force)
                const Mat3& C = (*damping)[i];
                W[0] += h * T(C(0, 0)), W[1] += h * T(C(0, 1)), W[2] += h * T(C(0, 2));
                W[3] += h * T(C(1, 1)), W[4] += h * T(C(1, 2)), W[5] += h * T(C(2, 2));
            }
            symmetricInverse(W, w);
            symmetricTimes(w, r, d);
        }
    });
}

// Runs the Jacobi iterations; the result ends up in dvA_.
template <class T>
void GatherKangCho<T>::jacobiSweeps(T h2, int iterations) {
    // Jacobi sweeps (eq. 11; one sweep is eq. 14): dv_i = W_ii^-1 (b_i + h^2 sum_{j free} J dv_j).
    for (int k = 0; k < iterations; ++k) {
        pool_.run(n_, [&](int begin, int end) {
            for (int i = begin; i < end; ++i) {
                T* out = &dvB_[3 * i];
                if (pinned_[i]) {
                    for (int a = 0; a < 3; ++a) out[a] = pin_[3 * i + a];
                    continue;
                }
                T s0 = 0, s1 = 0, s2 = 0;
                for (int e = adjStart_[i]; e < adjStart_[i + 1]; ++e) {
                    const int j = adjOther_[e];
                    if (pinned_[j]) continue;  // pinned columns are already in b_i
                    const int s = adjSpring_[e];
                    const T* q = &dvA_[3 * j];
                    const T uq = b_[s] * (ux_[s] * q[0] + uy_[s] * q[1] + uz_[s] * q[2]);
                    s0 += a_[s] * q[0] + uq * ux_[s];
                    s1 += a_[s] * q[1] + uq * uy_[s];
                    s2 += a_[s] * q[2] + uq * uz_[s];
                }
                const T* r = &rhs_[3 * i];
                const T y[3] = {r[0] + h2 * s0, r[1] + h2 * s1, r[2] + h2 * s2};
                symmetricTimes(&winv_[6 * i], y, out);
            }
        });
        std::swap(dvA_, dvB_);
    }
}

template <class T>
void GatherKangCho<T>::solve(const StepProblem& problem, int iterations, Points& dv, double* forcesMs) {
    const auto& [model, env, state, input, compressionRule] = problem;
    const auto t0 = std::chrono::steady_clock::now();
    if (modelId_ != model.id()) prepare(model);
    setPins(state, input);
    computeSprings(state, compressionRule);
    assembleParticles(env, state, input);
    if (forcesMs) *forcesMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    const T h = T(input.h);
    jacobiSweeps(h * h, iterations);
    dv.resize(3, n_);
    double* out = dv.data();
    for (std::size_t k = 0; k < dvA_.size(); ++k) out[k] = double(dvA_[k]);
}

template class GatherKangCho<float>;
template class GatherKangCho<double>;

}  // namespace cloth
