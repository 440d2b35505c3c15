#include "fine_system.h"

#include "../kernels.h"

namespace cloth {

namespace {

// base_i = m_i (1 + h c) I + h C_i (C_i: the implicit air's damping block, where given).
template <class T>
void diagonalBase(const Model& model, const StepInput& input, T h, T c, std::vector<T>& base) {
    const auto& mass = model.masses();
    for (int i = 0; i < model.particleCount(); ++i) {
        T* B = &base[6 * std::size_t(i)];
        const T md = T(mass[i]) * (T(1) + h * c);
        B[0] = B[3] = B[5] = md;
        B[1] = B[2] = B[4] = T(0);
        if (input.damping) {
            const Mat3& C = (*input.damping)[i];
            B[0] += h * T(C(0, 0)), B[1] += h * T(C(0, 1)), B[2] += h * T(C(0, 2));
            B[3] += h * T(C(1, 1)), B[4] += h * T(C(1, 2)), B[5] += h * T(C(2, 2));
        }
    }
}

// Arrays of blocks (6 numbers each) rounded to T.
template <class T>
void roundBlocks(const std::vector<double>& from, std::vector<T>& to, ThreadPool& pool) {
    to.resize(from.size());
    pool.run(int(from.size() / 6), [&](int begin, int end) {
        for (std::size_t q = 6 * std::size_t(begin); q < 6 * std::size_t(end); ++q) to[q] = T(from[q]);
    });
}

// A banded level 0's bands, free rows and compact spring arrays, rounded.
template <class T>
void roundBands(const FineSystem<double>& F, const Level<double>& from, FineSystem<T>& S, Level<T>& L,
                ThreadPool& pool) {
    const std::size_t arrays = 6 * (L.A.offsets.size() + 1);
    pool.run(L.A.n, [&](int begin, int end) {
        for (std::size_t a = 0; a < arrays; ++a) {
            const double* src = from.A.values.data() + a * from.A.stride + from.A.pad;
            T* dst = L.A.values.data() + a * L.A.stride + L.A.pad;
            for (int i = begin; i < end; ++i) dst[i] = T(src[i]);
        }
        for (int i = begin; i < end; ++i) S.band.freeRow[S.band.pad + i] = T(F.band.freeRow[F.band.pad + i]);
        for (int k = 0; k < int(S.band.offsets.size()); ++k)
            for (int q = 0; q < 4; ++q) {
                const double* src = F.band.sp(k, q);
                T* dst = S.band.sp(k, q);
                for (int i = begin; i < end; ++i) dst[i] = T(src[i]);
            }
    });
}

}  // namespace

template <class T>
void FineSystem<T>::prepare(const Model& model, Level<T>& L0) {
    const int n = model.particleCount();
    L0.A.n = n;
    L0.A.start = model.adjStart();
    L0.A.col = model.adjOther();
    L0.A.slot = model.adjSpring();
    L0.A.slots = model.springCount();
    if (band.assign(model, L0.A)) L0.springs = &band;
    else springs.assign(model);
    pinned.assign(n, 0);
    base.assign(6 * std::size_t(n), T(0));
    pinDv.assign(3 * std::size_t(n), T(0));
}

template <class T>
void FineSystem<T>::build(const StepProblem& problem, Level<T>& L0, ThreadPool& pool) {
    const auto& [model, env, state, input, rule] = problem;
    const T h = T(input.h), hh = h * h, c = T(env.drag);
    gatherPins(state, input, pinned, pinDv);
    diagonalBase(model, input, h, c, base);
    const double* ext = input.externalForce ? input.externalForce->data() : nullptr;
    const RowForces<T> rows{model.masses().data(), state.v.data(), ext,
                            {T(env.gravity.x()), T(env.gravity.y()), T(env.gravity.z())}, c, h};
    const FineInputs<T> in{state.x.data(), state.v.data(), h, hh, rule, pinned.data(), base.data(), pinDv.data(), rows};
    if (band.used()) {
        assembleBanded(band, in, L0, pool);
    } else {
        springs.compute(in, L0.A, pool);
        assembleGathered(springs, in, L0, pool);
    }
    h2 = hh;
    compressionRule = rule;
}

template <class T>
void FineSystem<T>::roundFrom(const FineSystem<double>& F, const Level<double>& from, Level<T>& L, ThreadPool& pool) {
    if (L.A.banded()) roundBands(F, from, *this, L, pool);
    else roundBlocks(from.A.values, L.A.values, pool);
    if (!L.A.blocks.empty()) roundBlocks(from.A.blocks, L.A.blocks, pool);
    roundBlocks(from.dinv, L.dinv, pool);
    roundBlocks(F.base, base, pool);
    pool.run(L.A.n, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) L.active[i] = T(from.active[i]);
    });
    pinned = F.pinned;
    h2 = T(F.h2);
    compressionRule = F.compressionRule;
}

template struct FineSystem<float>;
template struct FineSystem<double>;

}  // namespace cloth
