// cloth::Cloth, the library's own step: its stages in their order (air, solve, collisions),
// checked against the same library calls made by hand here, and its settings refused with the
// name of what is wrong.

#include <gtest/gtest.h>

#include "cloth/cloth.h"
#include "cloth/crossings.h"
#include "cloth/flag_on_pole.h"
#include "physics_support.h"

using namespace cloth;
using cloth::test::turningCarrier;

namespace {

ClothSettings flagSettings(const std::string& solver) {
    ClothSettings s;
    std::string error;
    EXPECT_TRUE(parseSolverConfig(solver, s.solver, &error)) << error;
    s.air = true;
    s.airParams.wind = Vec3(4, 0, 1);
    s.collisions = true;
    return s;
}

// The stages made by hand: the pins on the carrier, the air with its implicit blocks, the
// solver's step, then the colliders, each exactly once per tick.
void stepByHand(const ClothDesc& d, const ClothSettings& s, Solver& solver, State& state, double h,
                const RigidFrame& c, const std::vector<Collider>& colliders) {
    StepInput input;
    input.h = h;
    for (const Attachment& a : d.attachments) input.pins.push_back({a.particle, c.point(a.local), c.velocityAt(c.point(a.local))});
    Points air = Points::Zero(3, d.model.particleCount());
    std::vector<Mat3> jacobian, damping;
    addAirForces(d.model, state, s.airParams, air, &jacobian);
    airDamping(jacobian, damping);
    input.externalForce = &air;
    input.damping = &damping;
    ASSERT_EQ(solver.step(d.model, s.environment, state, input).status, StepStatus::Ok);
    std::vector<std::uint8_t> skip = d.collisionSkip;
    for (const Attachment& a : d.attachments) skip[std::size_t(a.particle)] = 1;
    resolveCollisions(colliders, s.thickness, &skip, state);
}

// The pole, and a floor the flag's lower rows reach (the flag hangs from 3 m to 2 m).
std::vector<Collider> collidersAt(const Pole& pole, const RigidFrame& c) {
    Collider floor;
    floor.center = Vec3(0, 2.3, 0);
    return {poleCollider(pole, c), floor};
}

}  // namespace

TEST(Cloth, StepsItsStagesInOrderAsTheLibraryCallsMadeByHand) {
    FlagDesc f;
    f.nx = 13, f.ny = 9;
    Pole pole;
    const ClothDesc desc = flagOnPole(f, pole, 0.015);
    const ClothSettings s = flagSettings("kangcho");
    Cloth cloth(desc, s, turningCarrier(0));
    std::unique_ptr<Solver> solver = makeSolver(s.solver);
    State byHand = cloth.state();
    const double h = 1.0 / 240;
    for (int k = 1; k <= 240; ++k) {
        const RigidFrame c = turningCarrier(k * h);
        const std::vector<Collider> colliders = collidersAt(pole, c);
        cloth.step(h, c, colliders);
        stepByHand(desc, s, *solver, byHand, h, c, colliders);
    }
    EXPECT_EQ(cloth.failures(), 0);
    EXPECT_EQ(cloth.steps(), 240);
    // Bit for bit: the same calls in the same order.
    EXPECT_EQ((cloth.state().x - byHand.x).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ((cloth.state().v - byHand.v).cwiseAbs().maxCoeff(), 0.0);
    // And the colliders mattered: without them the same run ends elsewhere.
    ClothSettings noCollisions = s;
    noCollisions.collisions = false;
    Cloth free(desc, noCollisions, turningCarrier(0));
    for (int k = 1; k <= 240; ++k) free.step(h, turningCarrier(k * h), collidersAt(pole, turningCarrier(k * h)));
    EXPECT_GT((free.state().x - cloth.state().x).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Cloth, AttachmentsLandOnTheCarrierAndTheProfileCountsEveryStage) {
    FlagDesc f;
    f.nx = 9, f.ny = 7;
    Pole pole;
    const ClothDesc desc = flagOnPole(f, pole, 0.015);
    ClothSettings s = flagSettings("kangcho");
    s.substeps = 3;
    Cloth cloth(desc, s, turningCarrier(0));
    const RigidFrame c = turningCarrier(0.1);
    EXPECT_TRUE(cloth.step(1.0 / 60, c, {poleCollider(pole, c)}));
    EXPECT_EQ(cloth.steps(), 3);
    for (const Attachment& a : desc.attachments)
        EXPECT_LT((cloth.state().x.col(a.particle) - c.point(a.local)).norm(), 1e-12);
    EXPECT_GT(cloth.profile().air, 0.0);
    EXPECT_GT(cloth.profile().collision, 0.0);
}

TEST(Cloth, RefusesBadSettingsNamingThemAndKeepsItsOwn) {
    FlagDesc f;
    f.nx = 5, f.ny = 5;
    const ClothDesc desc = flagOnPole(f, Pole{}, 0.015);
    ClothSettings bad = flagSettings("kangcho");
    bad.constraints.stretchLimit = -1;
    try {
        Cloth cloth(desc, bad, RigidFrame{});
        FAIL() << "a negative stretch limit was taken";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("constraints:"), std::string::npos) << e.what();
    }
    Cloth cloth(desc, flagSettings("multigrid"), RigidFrame{});
    EXPECT_THROW(cloth.reconfigure(bad), std::invalid_argument);
    EXPECT_EQ(cloth.settings().solver.name, "multigrid");
    ClothDesc none = desc;
    none.attachments.clear();
    EXPECT_THROW(Cloth(none, flagSettings("kangcho"), RigidFrame{}), std::invalid_argument);
}

namespace {

// Counts the stages a cloth runs.
struct StageCount : ClothObserver {
    int solve = 0, contact = 0;
    void stageBegins(ClothStage s) override {
        solve += s == ClothStage::Solve;
        contact += s == ClothStage::Contact;
    }
};

}  // namespace

namespace {

// The demo's flag at 33x33 with contact, 0.5 s on a carrier at 10 m/s turning at 0.6 rad/s
// (its free edge folds onto the cloth), stepped by `solver` in `substeps` per 240 Hz tick: the
// longest spring's stretch over the run, and the stages counted.
double worstStretchWithContact(const std::string& solver, int substeps, StageCount& count, int& subintervals,
                               int stride = 1, long long* applications = nullptr) {
    FlagDesc f;
    f.width = 1.5, f.height = 1.0, f.mass = 0.25, f.stiffness = Stiffness{1000, 100, 5}, f.onShell = true;
    Pole pole;
    const auto carrier = [](double t) {
        RigidFrame c;
        c.position = Vec3(0, 0, 10 * t);
        c.linearVelocity = Vec3(0, 0, 10);
        c.rotation = Eigen::AngleAxisd(0.6 * t, Vec3::UnitY());
        c.angularVelocity = Vec3(0, 0.6, 0);
        return c;
    };
    ClothSettings s = flagSettings(solver);
    s.airParams.wind = Vec3::Zero();
    s.constraints.tether = 0.02, s.constraints.stretchLimit = 0.1;
    s.environment.drag = 0.05;
    s.implicitAir = false;
    s.substeps = substeps;
    s.contact.enabled = true;
    s.contact.substepStride = stride;
    Cloth cloth(flagOnPole(f, pole, s.thickness), s, carrier(0));
    cloth.setObserver(&count);
    const double h = 1.0 / 240;
    double worst = 0;
    for (int k = 1; k <= 120; ++k) {
        cloth.step(h, carrier(k * h), {poleCollider(pole, carrier(k * h))});
        subintervals += cloth.contactReport().subintervals;
        for (const Spring& sp : cloth.model().springs())
            worst = std::max(worst, (cloth.state().x.col(sp.i) - cloth.state().x.col(sp.j)).norm() / sp.rest - 1);
    }
    EXPECT_EQ(cloth.failures(), 0) << solver;
    if (applications) *applications = cloth.contactTotal().applications;
    return worst;
}

}  // namespace

TEST(Cloth, ContactAtEverySubstepKeepsAFineStepsSpringsWhole) {
    // Contact runs after every substep, over the substep's motion: no spring of a fine-step
    // integrator ends over 15% long (without contact: 8-10%). Contact once per tick over many
    // substeps instead held back particles that the springs then pulled through: 308% within the
    // half second for the reference's integrator, 223% for small_steps.
    StageCount explicitCount;
    int subintervals = 0;
    // The reference's integrator: 24 substeps of the cloth, contact after each (by the cloth).
    EXPECT_LT(worstStretchWithContact("explicit", 24, explicitCount, subintervals), 0.15);
    EXPECT_EQ(explicitCount.solve, 120 * 24);
    EXPECT_EQ(explicitCount.contact, explicitCount.solve);
    // The true motion: substeps of its own, contact after each (inside the solver's step, handed
    // in by the cloth): at least one sub-interval per substep, and no stage of its own.
    StageCount smallCount;
    subintervals = 0;
    EXPECT_LT(worstStretchWithContact("small_steps:max_move=0.01", 1, smallCount, subintervals), 0.15);
    EXPECT_EQ(smallCount.contact, 0);
    EXPECT_GT(subintervals, 2 * 120);
}

TEST(Cloth, ContactAfterEveryFewSubstepsRunsThatMuchLessAndOncePerTickByTheCloth) {
    // small_steps at 33x33 with contact after every substep, every second and once per tick
    // (stride 0: then the cloth runs it after the step, a stage it tells the observer). Every
    // second substep and the last: about half the applications; springs still under 15% long.
    StageCount every, second, once;
    int subintervals = 0;
    long long a1 = 0, a2 = 0, a0 = 0;
    worstStretchWithContact("small_steps:max_move=0.01", 1, every, subintervals, 1, &a1);
    EXPECT_LT(worstStretchWithContact("small_steps:max_move=0.01", 1, second, subintervals, 2, &a2), 0.15);
    worstStretchWithContact("small_steps:max_move=0.01", 1, once, subintervals, 0, &a0);
    EXPECT_GT(a1, 2 * 120);  // several substeps a tick
    EXPECT_GT(a2, 0.4 * double(a1));
    EXPECT_LT(a2, 0.7 * double(a1));
    EXPECT_EQ(every.contact, 0);  // inside the solver's step
    EXPECT_EQ(once.contact, 120);
    EXPECT_EQ(a0, 120);
}

namespace {

// The demo's flag at 33x33 on small_steps paced at 1 cm, without gravity and air, at rest on a
// carrier at 30 m/s (12.5 cm a 240 Hz tick: 13 substeps for its pins' moves), contact after every
// substep or after every `strideMove` the cloth moves on its carrier, for `ticks` ticks; then the
// carrier stops dead (the cloth flies on at 30 m/s relative to it). The applications of each part.
std::pair<long long, long long> applicationsAtRestThenThrown(Scalar strideMove, int ticks) {
    FlagDesc f;
    f.width = 1.5, f.height = 1.0, f.mass = 0.25, f.stiffness = Stiffness{1000, 100, 5}, f.onShell = true;
    Pole pole;
    ClothSettings s = flagSettings("small_steps:max_move=0.01");
    s.air = false, s.collisions = false;
    s.environment.gravity = Vec3::Zero();
    s.contact.enabled = true;
    s.contact.strideMove = strideMove;
    const auto carrier = [](double t) {
        RigidFrame c;
        c.position = Vec3(0, 0, 30 * t);
        c.linearVelocity = Vec3(0, 0, 30);
        return c;
    };
    Cloth cloth(flagOnPole(f, pole, s.thickness), s, carrier(0));
    const double h = 1.0 / 240;
    for (int k = 1; k <= ticks; ++k) cloth.step(h, carrier(k * h), {});
    const long long atRest = cloth.contactTotal().applications;
    RigidFrame stopped = carrier(ticks * h);
    stopped.linearVelocity = Vec3::Zero();
    cloth.step(h, stopped, {});
    EXPECT_EQ(cloth.failures(), 0);
    return {atRest, cloth.contactTotal().applications - atRest};
}

}  // namespace

TEST(Cloth, ContactByMoveRunsAsOftenAsTheClothMovesOnItsCarrier) {
    // At rest on a carrier at 30 m/s, the cloth does not move on it: contact by move runs once a
    // tick (after the last substep), where after every substep it runs 13 times or more (the
    // springs' stability bound may ask for more substeps than the pins' moves). When the carrier
    // stops dead, the cloth flies 12.5 cm on it in the tick: contact after every 2 cm of that, at
    // least 12.5 / 2 times.
    const auto [everyAtRest, everyThrown] = applicationsAtRestThenThrown(0, 10);
    const auto [moveAtRest, moveThrown] = applicationsAtRestThenThrown(0.02, 10);
    EXPECT_GE(everyAtRest, 10 * 13);
    EXPECT_EQ(moveAtRest, 10);
    EXPECT_GE(moveThrown, 6);
    EXPECT_LE(moveThrown, everyThrown);
}

TEST(Cloth, APaperStepFlagTeleportedOneMetreWithContactEndsNoTickCrossed) {
    // The paper's step at 25x25 with contact: the carrier jumps 1 m, so in the carrier's frame the
    // step throws the flag 1 m, and the sheet, flat at both ends of the next step, folds on the way.
    // The checker (crossings.h, from the states alone) counts no crossing after any tick. A broad
    // phase that judged flatness from the step's two ends alone skipped the folding patches: 13
    // edges through the cloth after the jump's next tick, 61 after the one after.
    FlagDesc f;
    f.width = 1.5, f.height = 1.0, f.mass = 0.25, f.stiffness = Stiffness{1000, 100, 5}, f.onShell = true;
    f.nx = f.ny = 25;
    Pole pole;
    const auto carrier = [](int tick) {
        RigidFrame c;
        if (tick >= 10) c.position = Vec3(1, 0, 0);
        return c;
    };
    ClothSettings s = flagSettings("kangcho:iterations=1,precision=float,compression=on");
    s.airParams.wind = Vec3::Zero();
    s.constraints.tether = 0.02, s.constraints.stretchLimit = 0.1, s.constraints.stretchPasses = 4;
    s.environment.drag = 0.05;
    s.implicitAir = false;
    s.contact.enabled = true;
    Cloth cloth(flagOnPole(f, pole, s.thickness), s, carrier(0));
    int pairs = 0;
    for (int k = 1; k <= 12; ++k) {
        cloth.step(1.0 / 240, carrier(k), {poleCollider(pole, carrier(k))});
        CrossingScene scene;
        const auto [a, b] = poleAxis(pole);
        scene.capsules.push_back({carrier(k).point(a), carrier(k).point(b), pole.radius});
        const CrossingCounts crossed = countCrossings(cloth.model(), cloth.state().x, scene);
        EXPECT_EQ(crossed.total(), 0) << "tick " << k << ": " << crossed.poleEdges << " pole, " << crossed.selfEdges << " self";
        if (k >= 10) pairs += cloth.contactReport().selfPairs;
    }
    EXPECT_GT(pairs, 0);  // the folding patches were searched
    EXPECT_EQ(cloth.failures(), 0);
}
