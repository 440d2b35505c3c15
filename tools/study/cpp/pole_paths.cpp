#include "pole_paths.h"

#include <algorithm>
#include <cmath>

#include "engine/scene/input_script.h"
#include "engine/physics/vehicle_world.h"

namespace study {

// The chassis path of the demo's drive script, from the demo's own vehicle (Bullet).
PolePath drivePath(double duration) {
    const engine::InputScript script = engine::InputScript::load(std::string(FLAGSIM_ASSETS_DIR) + "/scripts/drive.json");
    engine::VehicleWorld world({});
    PolePath p;
    p.dt = 1.0 / 960;
    for (int k = 0; k * p.dt <= duration + 1e-9; ++k) {
        const engine::Actions a = script.sample(k * p.dt);
        world.setControls({a.throttle, a.brake, a.steer, a.handbrake});
        world.stepTick(p.dt);
        const engine::RigidPose c = world.chassis();
        Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
        t.linear() = c.rotation.toRotationMatrix();
        t.translation() = c.position;
        p.pose.push_back(t);
        p.linear.push_back(c.linearVelocity);
        p.angular.push_back(c.angularVelocity);
    }
    return p;
}

// Pins of column 0 for the carrier pose at time t (rest positions in the carrier frame).
std::vector<cloth::Pin> pinsAt(const cloth::Model& m, const Scene& s, double t) {
    std::vector<cloth::Pin> pins = cloth::pinColumn(m);
    if (!s.path) return pins;
    const std::size_t k = std::min(s.path->pose.size() - 1, std::size_t(std::lround(t / s.path->dt)));
    const Eigen::Isometry3d& T = s.path->pose[k];
    for (cloth::Pin& p : pins) {
        const Vec3 local = m.restPositions().col(p.particle);
        p.x = T * local;
        p.v = s.path->linear[k] + s.path->angular[k].cross(p.x - T.translation());
    }
    return pins;
}

cloth::State startState(const cloth::Model& m, const Scene& s) {
    cloth::State st = cloth::State::atRest(m);
    if (s.path) {
        const Eigen::Isometry3d& T = s.path->pose[0];
        for (cloth::Index i = 0; i < m.particleCount(); ++i) st.x.col(i) = T * Vec3(m.restPositions().col(i));
    }
    return st;
}

// The study's flag: n x n, structural and shear stiffness k, bend k/10 (the rest as
// cloth::HangingFlagDesc says).
cloth::HangingFlag studyFlag(int n, double k) {
    cloth::HangingFlagDesc d;
    d.nx = d.ny = n;
    d.stiffness = {k, k, k / 10};
    return cloth::makeHangingFlag(d);
}

}  // namespace study
