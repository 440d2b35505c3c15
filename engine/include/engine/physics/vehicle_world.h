#pragma once
// Bullet world with a ground (plane, bumps, a ramp) and a raycast vehicle (four wheels with
// suspension) driven by throttle, brake, steer and handbrake. y is up; the vehicle drives along
// its local +z (right-handed: x = left, y = up, z = forward).
//
// The world steps in fixed ticks: each stepTick is exactly one of Bullet's internal ticks.

#include <Eigen/Geometry>
#include <memory>
#include <vector>

namespace engine {

struct VehicleControls {
    double throttle = 0;   // -1..1, negative reverses
    double brake = 0;      // 0..1
    double steer = 0;      // -1..1, positive turns left
    double handbrake = 0;  // 0..1
};

struct VehicleParams {
    double mass = 800;                 // kg
    Eigen::Vector3d halfExtents = {0.9, 0.35, 2.0};  // chassis box, m
    // The box's centre sits this far above the centre of mass: a low centre of mass keeps hard
    // braking and sharp turns from tipping the car over.
    double boxOffset = 0.5;
    double wheelConnectionHeight = 0.3;  // above the centre of mass
    double engineForce = 2000;         // N per rear wheel at full throttle
    double brakeForce = 200;           // per wheel at full brake
    double maxSteer = 0.5;             // rad
    double steerRate = 2.5;            // rad/s: the wheel cannot snap from lock to lock
    double wheelRadius = 0.38, wheelWidth = 0.25;
    double suspensionRestLength = 0.3;
    double suspensionStiffness = 30, dampingRelaxation = 2.3, dampingCompression = 4.4;
    double frictionSlip = 1.4, rollInfluence = 0.02;  // grip ~1.4 g; low roll influence
    double steerSpeedFalloff = 12;     // m/s: steering lock halves at this speed
    Eigen::Vector3d spawn = {0, 1.0, 0};
    double heading = 0;                // rad about +y
};

// A static prop of the ground, for rendering: a box or a cylinder (axis along local y).
struct GroundProp {
    enum class Shape { Box, Cylinder } shape = Shape::Box;
    Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
    Eigen::Vector3d halfExtents = Eigen::Vector3d::Zero();  // box; cylinder: (r, half height, r)
};

struct RigidPose {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d linearVelocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();
};

class VehicleWorld {
public:
    explicit VehicleWorld(const VehicleParams& params);
    ~VehicleWorld();
    VehicleWorld(const VehicleWorld&) = delete;
    VehicleWorld& operator=(const VehicleWorld&) = delete;

    void setControls(const VehicleControls& controls);
    // One fixed tick of length dt (stepSimulation(dt, 1, dt)). Returns the length Bullet
    // integrated: dt in Bullet's scalar precision (float in Debian's build).
    double stepTick(double dt);

    RigidPose chassis() const;  // the rigid body's own transform, not the interpolated one
    double speed() const;       // m/s along the ground
    int wheelCount() const;
    Eigen::Isometry3d wheelTransform(int i) const;
    const VehicleParams& params() const { return params_; }
    const std::vector<GroundProp>& props() const { return props_; }
    double groundSize() const { return 600; }

    static int worldsCreated();  // process-wide count

    // Routes Bullet's BT_PROFILE zones to these functions (null restores Bullet's own). Zones fire only when
    // the Bullet library was built with profiling.
    static void routeProfileZones(void (*enter)(const char*), void (*leave)());

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    VehicleParams params_;
    std::vector<GroundProp> props_;
};

}  // namespace engine
