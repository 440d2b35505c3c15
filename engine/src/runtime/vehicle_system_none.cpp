// The vehicle subsystem in a build without Bullet: a scene that declares it gets a clear error.

#include "engine/scene/config_error.h"
#include "runtime/vehicle_system.h"

namespace engine {

class VehicleWorld {};
struct GroundProp {};

VehicleSystem::VehicleSystem(const SceneConfig& scene, Profiler*) {
    throw ConfigError(scene.file + ": subsystems: scene '" + scene.name +
                      "' needs 'vehicle', but this build has no Bullet (FLAGSIM_WITH_BULLET=OFF)");
}
VehicleSystem::~VehicleSystem() = default;
int VehicleSystem::worldsCreated() { return 0; }
void VehicleSystem::setActions(const Actions&) {}
double VehicleSystem::stepTick(double dt) { return dt; }
RigidFrame VehicleSystem::carrier() const { return {}; }
PoleMount VehicleSystem::poleMount() const { return mount_; }
cloth::Collider VehicleSystem::bodyCollider() const { return {}; }
cloth::Collider VehicleSystem::bodySolid() const { return {}; }
Eigen::Vector3d VehicleSystem::forward() const { return Eigen::Vector3d::UnitZ(); }
Eigen::Isometry3d VehicleSystem::chassisTransform() const { return Eigen::Isometry3d::Identity(); }
int VehicleSystem::wheelCount() const { return 0; }
Eigen::Isometry3d VehicleSystem::wheelTransform(int) const { return Eigen::Isometry3d::Identity(); }
Eigen::Vector3d VehicleSystem::bodyOffset() const { return Eigen::Vector3d::Zero(); }
double VehicleSystem::wheelRadius() const { return 0; }
double VehicleSystem::wheelWidth() const { return 0; }
Eigen::Vector3d VehicleSystem::chassisHalfExtents() const { return Eigen::Vector3d::Zero(); }
double VehicleSystem::speed() const { return 0; }
const std::vector<GroundProp>& VehicleSystem::props() const {
    static const std::vector<GroundProp> none;
    return none;
}

}  // namespace engine
