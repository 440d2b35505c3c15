#include "drive_case.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "engine/scene/input_script.h"
#include "engine/physics/vehicle_world.h"

namespace study {

namespace {

using engine::RigidFrame;

constexpr double kDriveHz = 960;

engine::VehicleParams vehicleOf(const engine::SceneConfig& s) {
    engine::VehicleParams p;
    p.mass = s.vehicle.mass;
    p.engineForce = s.vehicle.engineForce;
    p.brakeForce = s.vehicle.brakeForce;
    p.maxSteer = s.vehicle.maxSteer;
    p.spawn = Eigen::Vector3d(s.vehicle.spawn[0], s.vehicle.spawn[1], s.vehicle.spawn[2]);
    p.heading = s.vehicle.heading;
    return p;
}

// The pole's frame at each 1/960 s: the chassis frame with its origin moved to the pole's base.
std::vector<RigidFrame> recordPole(const engine::SceneConfig& demo) {
    const engine::InputScript script = engine::InputScript::load(demo.script);
    engine::VehicleWorld world(vehicleOf(demo));
    const Eigen::Vector3d offset(demo.vehicle.poleOffset[0], demo.vehicle.poleOffset[1], demo.vehicle.poleOffset[2]);
    std::vector<RigidFrame> frames;
    for (int k = 0; k <= int(std::ceil(demo.duration * kDriveHz)); ++k) {
        if (k > 0) {
            const engine::Actions a = script.sample((k - 1) / kDriveHz);
            world.setControls({a.throttle, a.brake, a.steer, a.handbrake});
            world.stepTick(1 / kDriveHz);
        }
        const engine::RigidPose c = world.chassis();
        RigidFrame chassis{c.position, c.rotation, c.linearVelocity, c.angularVelocity};
        RigidFrame pole = chassis;
        pole.position = chassis.point(offset);
        pole.linearVelocity = chassis.velocityAt(pole.position);
        frames.push_back(pole);
    }
    return frames;
}

// Linear between two recorded frames (the rotation by slerp).
RigidFrame between(const RigidFrame& a, const RigidFrame& b, double s) {
    RigidFrame c;
    c.position = a.position + s * (b.position - a.position);
    c.rotation = a.rotation.slerp(s, b.rotation);
    c.linearVelocity = a.linearVelocity + s * (b.linearVelocity - a.linearVelocity);
    c.angularVelocity = a.angularVelocity + s * (b.angularVelocity - a.angularVelocity);
    return c;
}

}  // namespace

Extreme driveCase(const engine::SceneConfig& demo) {
    auto frames = std::make_shared<const std::vector<RigidFrame>>(recordPole(demo));
    Extreme x{"drive", demo.duration, [frames](double t) {
                  const double at = std::clamp(t * kDriveHz, 0.0, double(frames->size() - 1));
                  const std::size_t k = std::min(std::size_t(at), frames->size() - 2);
                  return between((*frames)[k], (*frames)[k + 1], at - double(k));
              }};
    x.flutter = true;
    return x;
}

}  // namespace study
