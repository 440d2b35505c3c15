#pragma once
// The vehicle subsystem as the runtime sees it: Bullet's world and raycast vehicle, driven by
// actions, one fixed physics tick at a time.

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "cloth/collision.h"
#include "engine/flag/flag.h"
#include "engine/scene/input_script.h"
#include "engine/mesh.h"
#include "engine/profile/profiler.h"
#include "engine/scene/scene.h"

namespace engine {

class VehicleWorld;
struct GroundProp;

class VehicleSystem {
public:
    // Throws ConfigError when this build has no Bullet.
    VehicleSystem(const SceneConfig& scene, Profiler* profiler);
    ~VehicleSystem();
    static int worldsCreated();  // Bullet worlds ever constructed in this process

    void setActions(const Actions& actions);
    // One fixed tick; returns the length Bullet integrated (dt in Bullet's scalar precision).
    double stepTick(double dt);

    RigidFrame carrier() const;        // chassis pose and velocity
    PoleMount poleMount() const;       // the pole in the chassis frame
    cloth::Collider bodyCollider() const;
    // The body's box in the chassis frame: a solid the flag's contact keeps its edges out of.
    cloth::Collider bodySolid() const;
    Eigen::Vector3d forward() const;   // world-space driving direction
    Eigen::Isometry3d chassisTransform() const;
    int wheelCount() const;
    Eigen::Isometry3d wheelTransform(int i) const;
    double wheelRadius() const;
    double wheelWidth() const;
    Eigen::Vector3d chassisHalfExtents() const;
    Eigen::Vector3d bodyOffset() const;  // the chassis box centre in the chassis frame
    double speed() const;
    const std::vector<GroundProp>& props() const;  // static ground features, for rendering

private:
    std::unique_ptr<VehicleWorld> world_;
    PoleMount mount_;
};

}  // namespace engine
