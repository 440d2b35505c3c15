// Bullet's btSoftBody as a solver kind of the study (registerSolverKind), so that the front runs
// it on the same flags, paths and air as every solver of this library: bullet_softbody steps the
// flag's particles, masses and springs (as Bullet's links, kLST = 1: as stiff as its solver
// allows) with Bullet's own position solver; the pins are kinematic nodes moved to their targets;
// the air and the drag come in as external forces. A peer for the study only: the library does
// not link Bullet.

#include "bullet_kind.h"

#include <chrono>
#include <memory>

#include "cloth/diagnostics.h"
#include "cloth/solver_kind.h"
#include "cloth/step_commit.h"
#include "peer_force.h"
#include "peers/bullet_cloth.h"

namespace study {

namespace {

struct BulletSettings {
    int iterations = 10;
};

class BulletSolver final : public cloth::Solver {
public:
    cloth::StepResult step(const cloth::Model& model, const cloth::Environment& env, cloth::State& state,
                           const cloth::StepInput& input) override {
        using namespace cloth;
        if (const Index bad = firstNonFinite(state); bad >= 0) return {StepStatus::NonFinite, bad};
        if (!bullet_ || model.id() != model_)
            bullet_ = std::make_unique<peer::BulletCloth>(model, state, input.pins, settings<BulletSettings>().iterations);
        model_ = model.id();
        const auto t0 = std::chrono::steady_clock::now();
        peerForce(model, env, state, input, force_);  // the drag and the air; gravity is Bullet's own
        scratch_ = state;
        bullet_->step(input.h, input.pins, &force_, scratch_);
        dv_ = scratch_.v - state.v;
        profile_ = {0, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(), 0};
        StepResult r = commitStep(model, constraints_, input, *pool_, state, scratch_, StepResult{});
        r.iterations = settings<BulletSettings>().iterations;
        return r;
    }

private:
    std::unique_ptr<peer::BulletCloth> bullet_;
    std::uint64_t model_ = 0;
    cloth::Points force_;
    cloth::State scratch_;
};

}  // namespace

void registerBulletSoftBody() {
    using namespace cloth;
    if (findSolverKind("bullet_softbody")) return;
    using B = BulletSettings;
    using key = SolverKeys;
    registerSolverKind({"bullet_softbody",
                        "Bullet's btSoftBody (a study peer): the springs as links, Bullet's position solver",
                        defaultsTo<B>,
                        withCommon({key::shown(key::integer("iterations", &B::iterations, 1, 1000,
                                                            "Bullet's position-solver iterations (piterations)"))},
                                   false),
                        {},
                        createSolver<BulletSolver>});
}

}  // namespace study
