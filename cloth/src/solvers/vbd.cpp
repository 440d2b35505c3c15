// vbd: Vertex Block Descent (Chen, Macklin et al. 2024). A substep of length h minimizes the
// backward Euler incremental potential in the springs,
//   G(x) = sum_i m_i / (2 h^2) |x_i - y_i|^2 + sum_s k_s / 2 (|x_j - x_i| - l0_s)^2,
// y = x_n + h v*, with v* the velocity after gravity, the environment's drag and the external force
// (the air), the last two implicit in velocity (StepInput::damping), as xpbd predicts it. So its
// fixed point is xpbd's and, without air or drag, backward Euler's. Each pass visits the vertices
// color by color (no spring joins two vertices of one color) and moves each free vertex by one
// Newton step on G with the others held: x_i += H_i^-1 f_i, with
//   f_i = -m_i / h^2 (x_i - y_i) - sum_s k_s (l - l0) u,   u = (x_i - x_j) / l,
//   H_i = m_i / h^2 I + sum_s k_s (u u^T + max(0, 1 - l0 / l) (I - u u^T)),
// each spring's block clamped to positive semi-definite under compression (the paper's eq. 17 in
// spirit). A color's vertices are independent, so they split among the threads with the same bits
// for any count. Then v = (x - x_n) / h. Pinned particles go to their targets and stay there.

#include "cloth/solvers/vbd_settings.h"
#include "cloth/solver_kind.h"
#include "solvers/step_common.h"

#include <algorithm>

#include "cloth/diagnostics.h"

namespace cloth {

namespace {

// The springs at each vertex (compressed rows: the other end, stiffness and rest length side by
// side) and the vertices by color: a greedy coloring in vertex order, so that no spring joins two
// vertices of one color.
struct VertexGraph {
    struct End {
        Index other = 0;
        Scalar k = 0, rest = 0;
    };
    std::uint64_t model = 0;
    std::vector<Index> start;  // vertex i's springs: ends[start[i] .. start[i + 1])
    std::vector<End> ends;
    std::vector<std::vector<Index>> colors;

    void build(const Model& m) {
        const Index n = m.particleCount();
        const auto& springs = m.springs();
        start.assign(n + 1, 0);
        for (const Spring& s : springs) ++start[s.i + 1], ++start[s.j + 1];
        for (Index i = 0; i < n; ++i) start[i + 1] += start[i];
        ends.resize(start[n]);
        std::vector<Index> fill(start.begin(), start.end() - 1);
        for (const Spring& s : springs) ends[fill[s.i]++] = {s.j, s.k, s.rest}, ends[fill[s.j]++] = {s.i, s.k, s.rest};
        std::vector<int> color(n, -1);
        colors.clear();
        for (Index i = 0; i < n; ++i) {
            std::vector<bool> taken(colors.size() + 1, false);
            for (Index k = start[i]; k < start[i + 1]; ++k)
                if (color[ends[k].other] >= 0) taken[color[ends[k].other]] = true;
            color[i] = int(std::find(taken.begin(), taken.end(), false) - taken.begin());
            if (color[i] == int(colors.size())) colors.emplace_back();
            colors[color[i]].push_back(i);
        }
        model = m.id();
    }
};

class VbdSolver final : public Solver {
public:
    StepResult step(const Model& model, const Environment& env, State& state, const StepInput& input) override {
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        const VbdSettings& s = settings<VbdSettings>();
        profile_ = {};
        if (graph_.model != model.id()) graph_.build(model);
        setPinned(model, input);
        scratch_.x = state.x, scratch_.v = state.v, x0_ = state.x;
        StepInput sub = input;
        sub.h = input.h / s.substeps;
        for (int k = 0; k < s.substeps; ++k) substep(model, env, sub, Scalar(k + 1) / s.substeps);
        const auto t0 = Clock::now();
        dv_ = scratch_.v - state.v;
        StepResult result;
        result.iterations = s.iterations * s.substeps;
        result = commitStep(model, constraints_, input, *pool_, state, scratch_, result);
        profile_.integrateMs = msSince(t0);
        return result;
    }

private:
    // The step's pins on particles of the model (pins_), and each particle's flag (pinned_).
    void setPinned(const Model& model, const StepInput& input) {
        pinned_.assign(std::size_t(model.particleCount()), 0);
        pins_.clear();
        for (const Pin& p : input.pins)
            if (p.particle >= 0 && p.particle < model.particleCount()) pinned_[p.particle] = 1, pins_.push_back(p);
    }

    // One substep from scratch_ (x_n, v_n) of length sub.h; the pins at the fraction `f` of the way
    // from where they were at the step's start to its targets.
    void substep(const Model& model, const Environment& env, const StepInput& sub, Scalar f) {
        auto t0 = Clock::now();
        xStart_ = scratch_.x;
        predict(model, env, sub);
        for (const Pin& p : pins_)
            scratch_.x.col(p.particle) = f == 1 ? p.x : Vec3(x0_.col(p.particle) + f * (p.x - x0_.col(p.particle)));
        y_ = scratch_.x;
        profile_.forcesMs += msSince(t0);
        t0 = Clock::now();
        for (int pass = 0; pass < settings<VbdSettings>().iterations; ++pass)
            for (const std::vector<Index>& color : graph_.colors)
                pool_->run(int(color.size()), [&](int b, int e) {
                    for (int k = b; k < e; ++k) descend(model, color[k], sub.h);
                });
        for (Index i = 0; i < model.particleCount(); ++i) scratch_.v.col(i) = (scratch_.x.col(i) - xStart_.col(i)) / sub.h;
        if (f == 1)
            for (const Pin& p : pins_) scratch_.v.col(p.particle) = p.v;
        profile_.solveMs += msSince(t0);
    }

    // y: x_n + h v* (step_common.h's predictVelocity).
    void predict(const Model& model, const Environment& env, const StepInput& sub) {
        for (Index i = 0; i < model.particleCount(); ++i)
            if (!pinned_[i]) scratch_.x.col(i) += sub.h * predictVelocity(model, env, sub, i, scratch_.v.col(i), sub.h);
    }

    // One Newton step on G for vertex i with the others held.
    void descend(const Model& model, Index i, Scalar h) {
        if (pinned_[i]) return;
        const Scalar inertia = model.masses()[i] / (h * h);
        const Vec3 xi = scratch_.x.col(i);
        Vec3 f = -inertia * (xi - y_.col(i));
        Scalar across = inertia;  // H = across I + sum over springs of along_s u u^T
        Mat3 H = Mat3::Zero();
        for (Index k = graph_.start[i]; k < graph_.start[i + 1]; ++k) {
            const VertexGraph::End& s = graph_.ends[k];
            const Vec3 d = xi - scratch_.x.col(s.other);
            const Scalar l = d.norm();
            if (l < kMinSpringLength || !(s.k > 0)) continue;
            const Vec3 u = d / l;
            const Scalar c = std::max(Scalar(0), 1 - s.rest / l);
            f -= s.k * (l - s.rest) * u;
            across += s.k * c;
            H.noalias() += (s.k * (1 - c)) * (u * u.transpose());
        }
        H.diagonal().array() += across;
        scratch_.x.col(i) = xi + H.inverse() * f;
    }

    VertexGraph graph_;
    std::vector<std::uint8_t> pinned_;
    std::vector<Pin> pins_;
    State scratch_;
    Points x0_, xStart_, y_;  // the step's start, the substep's, the substep's inertial target
};

}  // namespace

FLAGSIM_SOLVER_KIND(vbd) {
    using V = VbdSettings;
    using key = SolverKeys;
    return {"vbd", "Vertex Block Descent: per-vertex Newton steps on backward Euler's potential, color by color",
            defaultsTo<V>,
            withCommon({key::shown(key::integer("iterations", &V::iterations, 1, 10000, "passes over the vertex colors per substep")),
                        key::shown(key::integer("substeps", &V::substeps, 1, 100000, "substeps per step")),
                        threadsKey<V>()},
                       false),
            {},
            createSolver<VbdSolver>};
}

}  // namespace cloth
