// The vehicle subsystem on Bullet.

#include "runtime/vehicle_system.h"

#include "engine/physics/vehicle_world.h"

namespace engine {

namespace {

// Bullet's profile zones land in the running scene's profiler (one vehicle scene at a time).
Profiler* gZoneProfiler = nullptr;
void enterZone(const char* name) {
    if (gZoneProfiler) gZoneProfiler->enterZone(name);
}
void leaveZone() {
    if (gZoneProfiler) gZoneProfiler->leaveZone();
}

}  // namespace

VehicleSystem::VehicleSystem(const SceneConfig& scene, Profiler* profiler) {
    VehicleParams p;
    p.mass = scene.vehicle.mass;
    p.engineForce = scene.vehicle.engineForce;
    p.brakeForce = scene.vehicle.brakeForce;
    p.maxSteer = scene.vehicle.maxSteer;
    p.spawn = Eigen::Vector3d(scene.vehicle.spawn[0], scene.vehicle.spawn[1], scene.vehicle.spawn[2]);
    p.heading = scene.vehicle.heading;
    world_ = std::make_unique<VehicleWorld>(p);
    mount_.base = Eigen::Vector3d(scene.vehicle.poleOffset[0], scene.vehicle.poleOffset[1],
                                  scene.vehicle.poleOffset[2]);
    mount_.height = scene.vehicle.poleHeight;
    mount_.radius = scene.vehicle.poleRadius;
    mount_.trailing = -Eigen::Vector3d::UnitZ();  // the vehicle drives along +z
    if (profiler && (scene.subsystems & kProfiling)) {
        gZoneProfiler = profiler;
        VehicleWorld::routeProfileZones(&enterZone, &leaveZone);
    }
}

int VehicleSystem::worldsCreated() { return VehicleWorld::worldsCreated(); }

VehicleSystem::~VehicleSystem() {
    world_.reset();  // its teardown still reports zones
    VehicleWorld::routeProfileZones(nullptr, nullptr);
    gZoneProfiler = nullptr;
}

void VehicleSystem::setActions(const Actions& a) {
    world_->setControls({a.throttle, a.brake, a.steer, a.handbrake});
}
double VehicleSystem::stepTick(double dt) { return world_->stepTick(dt); }

RigidFrame VehicleSystem::carrier() const {
    const RigidPose p = world_->chassis();
    return {p.position, p.rotation, p.linearVelocity, p.angularVelocity};
}

PoleMount VehicleSystem::poleMount() const { return mount_; }

cloth::Collider VehicleSystem::bodyCollider() const {
    const RigidFrame c = carrier();
    cloth::Collider box;
    box.shape = cloth::Collider::Shape::Box;
    box.center = c.point(bodyOffset());
    box.rotation = c.rotation.toRotationMatrix();
    box.halfExtents = world_->params().halfExtents;
    box.velocity = c.velocityAt(box.center);
    return box;
}

cloth::Collider VehicleSystem::bodySolid() const {
    cloth::Collider box;
    box.shape = cloth::Collider::Shape::Box;
    box.center = bodyOffset();
    box.halfExtents = world_->params().halfExtents;
    return box;
}

Eigen::Vector3d VehicleSystem::forward() const { return world_->chassis().rotation * Eigen::Vector3d::UnitZ(); }

Eigen::Isometry3d VehicleSystem::chassisTransform() const {
    const RigidPose p = world_->chassis();
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = p.rotation.toRotationMatrix();
    t.translation() = p.position;
    return t;
}

int VehicleSystem::wheelCount() const { return world_->wheelCount(); }
Eigen::Isometry3d VehicleSystem::wheelTransform(int i) const { return world_->wheelTransform(i); }
Eigen::Vector3d VehicleSystem::bodyOffset() const { return Eigen::Vector3d(0, world_->params().boxOffset, 0); }
double VehicleSystem::wheelRadius() const { return world_->params().wheelRadius; }
double VehicleSystem::wheelWidth() const { return world_->params().wheelWidth; }
Eigen::Vector3d VehicleSystem::chassisHalfExtents() const { return world_->params().halfExtents; }
double VehicleSystem::speed() const { return world_->speed(); }
const std::vector<GroundProp>& VehicleSystem::props() const { return world_->props(); }

}  // namespace engine
