#pragma once
// The Kang & Cho step for models whose springs fall into a few constant index offsets: every
// grid does (right, down, two diagonals, right-2, down-2: six "families"). The system and the
// iterates are the ones of GatherKangCho (kangcho/gather.h) and of the assembled reference; only
// the data layout differs:
//  - positions, velocities and every per-particle quantity are structure-of-arrays, padded with
//    zeros on both sides by the largest offset, so no loop needs a bounds test;
//  - spring s of family f with offset d joins slot p to p + d; its u, a, b and force magnitude
//    live at index p of the family's arrays, and a slot with no spring has k = 0 (it
//    contributes exact zeros);
//  - particle i meets family f twice, at slots i (other end i + d) and i - d (other end i - d):
//    contiguous loads with constant offsets, so every loop vectorizes with no gathers.
// The particle passes hold each particle's sums in registers, a pack of 8 floats or 4 doubles at a
// time (pack.h), while they walk the families. Every kernel is compiled for three CPU levels
// (simd.h) and the loader picks the one the CPU runs (GCC target_clones). A pack and a scalar
// round alike, so neither the CPU level nor the thread count (loops are split across threads in
// blocks of 8 elements) changes a bit of the result.

#include <vector>

#include "kangcho/layout.h"

namespace cloth {

// The offsets of a model's springs, if they form at most kMaxFamilies families with one spring
// per (lower end, offset) and the padded slots cost at most twice the springs; else empty.
std::vector<int> springFamilies(const Model& model);
constexpr int kMaxFamilies = 8;

template <class T>
class StencilKangCho final : public KangChoLayout {
public:
    // offsets: springFamilies(model) of the model it will step, not empty.
    StencilKangCho(ThreadPool& pool, std::vector<int> offsets) : KangChoLayout(pool), offsets_(std::move(offsets)) {}
    void solve(const StepProblem& problem, int iterations, Points& dv, double* forcesMs) override;

    // One padded structure-of-arrays vector: element i at data()[pad + i].
    struct Field {
        std::vector<T> storage;
        T* at(int pad) { return storage.data() + pad; }
    };

private:
    void prepare(const Model& model);
    void loadFields(const Environment& env, const State& state, const StepInput& input);
    void setPins(const State& state, const StepInput& input);
    void loadDamping(const StepInput& input, T h);
    void computeSprings(bool compressionRule);
    void writeResult(Points& dv);
    template <class Fn>
    void forBlocks(int n, const Fn& fn);

    int n_ = 0, pad_ = 0;
    std::vector<int> offsets_;
    // Per family: stiffness and rest length per slot (static); u, a, b, force magnitude (per step).
    struct Family {
        Field k, rest, ux, uy, uz, a, b, fm;
    };
    std::vector<Family> families_;
    // w = v + the prescribed dv of pinned particles; pin = that dv (0 if free).
    std::vector<int> pinnedList_;
    Field mass_, x_[3], v_[3], w_[3], f0_[3], pin_[3], pinned_, rhs_[3], winv_[6], dvA_[3], dvB_[3];
    Field damp_[6];  // h C_i (xx xy xz yy yz zz)
    bool dampingLoaded_ = false;
};

extern template class StencilKangCho<float>;
extern template class StencilKangCho<double>;

}  // namespace cloth
