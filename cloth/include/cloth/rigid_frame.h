#pragma once
// A rigid frame and its velocity: what carries a cloth's attachments (a vehicle's chassis, or the
// world for a fixed pole). x_world = position + rotation * x_local.

#include <Eigen/Geometry>

#include "cloth/types.h"

namespace cloth {

struct RigidFrame {
    Vec3 position = Vec3::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    Vec3 linearVelocity = Vec3::Zero();
    Vec3 angularVelocity = Vec3::Zero();
    Vec3 point(const Vec3& local) const { return position + rotation * local; }
    Vec3 velocityAt(const Vec3& world) const { return linearVelocity + angularVelocity.cross(world - position); }
};

}  // namespace cloth
