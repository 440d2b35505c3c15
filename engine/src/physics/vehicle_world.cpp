#include "engine/physics/vehicle_world.h"

#include <btBulletDynamicsCommon.h>

#include <LinearMath/btQuickprof.h>
#include <algorithm>
#include <atomic>
#include <cmath>

namespace engine {

namespace {

std::atomic<int> gWorlds{0};

btVector3 bt(const Eigen::Vector3d& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }
Eigen::Vector3d eig(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

Eigen::Isometry3d toIsometry(const btTransform& t) {
    Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
    const btQuaternion q = t.getRotation();
    m.linear() = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).toRotationMatrix();
    m.translation() = eig(t.getOrigin());
    return m;
}

// The ground's props: a field of low bumps across the road ahead, and a ramp.
std::vector<GroundProp> groundProps() {
    std::vector<GroundProp> props;
    for (int i = 0; i < 6; ++i) {  // cylinders lying across the road, mostly sunk: 8 cm bumps
        const double r = 0.35, z = 18 + 2.5 * i;
        GroundProp prop;
        prop.shape = GroundProp::Shape::Cylinder;
        prop.halfExtents = {r, 4.0, r};
        prop.transform.translation() = Eigen::Vector3d(0, 0.08 - r, z);
        prop.transform.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        props.push_back(prop);
    }
    {   // a ramp to the right of the start line
        GroundProp prop;
        prop.halfExtents = {3.0, 0.5, 6.0};
        prop.transform.translation() = Eigen::Vector3d(-12, -0.1, 40);
        prop.transform.linear() = Eigen::AngleAxisd(-0.12, Eigen::Vector3d::UnitX()).toRotationMatrix();
        props.push_back(prop);
    }
    return props;
}

}  // namespace

struct VehicleWorld::Impl {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btRigidBody>> statics;
    std::unique_ptr<btDefaultMotionState> chassisMotion;
    std::unique_ptr<btRigidBody> chassis;
    std::unique_ptr<btVehicleRaycaster> raycaster;
    std::unique_ptr<btRaycastVehicle> vehicle;
    VehicleControls controls;
    double steering = 0;

    ~Impl() {
        if (vehicle) world.removeVehicle(vehicle.get());
        if (chassis) world.removeRigidBody(chassis.get());
        for (auto& b : statics) world.removeRigidBody(b.get());
    }

    btRigidBody* addStatic(std::unique_ptr<btCollisionShape> shape, const btTransform& t) {
        btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape.get());
        info.m_startWorldTransform = t;
        info.m_friction = 1.0;
        auto body = std::make_unique<btRigidBody>(info);
        world.addRigidBody(body.get());
        shapes.push_back(std::move(shape));
        statics.push_back(std::move(body));
        return statics.back().get();
    }

    void addGround(const std::vector<GroundProp>& props);
    void addChassis(const VehicleParams& p);
    void addVehicle(const VehicleParams& p);
};

// Adds the ground: an infinite plane, then the props.
void VehicleWorld::Impl::addGround(const std::vector<GroundProp>& props) {
    addStatic(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0), btTransform::getIdentity());
    for (const GroundProp& prop : props) {
        std::unique_ptr<btCollisionShape> shape;
        if (prop.shape == GroundProp::Shape::Box) shape = std::make_unique<btBoxShape>(bt(prop.halfExtents));
        else shape = std::make_unique<btCylinderShape>(bt(prop.halfExtents));
        btTransform t;
        t.setOrigin(bt(prop.transform.translation()));
        const Eigen::Quaterniond q(prop.transform.linear());
        t.setRotation(btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())));
        addStatic(std::move(shape), t);
    }
}

// Adds the chassis, a box whose centre of mass sits low enough that hard turns do not roll it.
void VehicleWorld::Impl::addChassis(const VehicleParams& p) {
    auto compound = std::make_unique<btCompoundShape>();
    auto box = std::make_unique<btBoxShape>(bt(p.halfExtents));
    btTransform local;
    local.setIdentity();
    local.setOrigin(btVector3(0, btScalar(p.boxOffset), 0));
    compound->addChildShape(local, box.get());
    btVector3 inertia;
    compound->calculateLocalInertia(btScalar(p.mass), inertia);
    btTransform start;
    start.setIdentity();
    start.setOrigin(bt(p.spawn));
    start.setRotation(btQuaternion(btVector3(0, 1, 0), btScalar(p.heading)));
    chassisMotion = std::make_unique<btDefaultMotionState>(start);
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(p.mass), chassisMotion.get(),
                                                  compound.get(), inertia);
    chassis = std::make_unique<btRigidBody>(info);
    // Without this the chassis falls asleep at rest and ignores the engine.
    chassis->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(chassis.get());
    shapes.push_back(std::move(box));
    shapes.push_back(std::move(compound));
}

// Adds the raycast vehicle on the chassis: four wheels with their suspension and grip.
void VehicleWorld::Impl::addVehicle(const VehicleParams& p) {
    btRaycastVehicle::btVehicleTuning tuning;
    tuning.m_suspensionStiffness = btScalar(p.suspensionStiffness);
    tuning.m_suspensionDamping = btScalar(p.dampingRelaxation);
    tuning.m_suspensionCompression = btScalar(p.dampingCompression);
    tuning.m_frictionSlip = btScalar(p.frictionSlip);
    raycaster = std::make_unique<btDefaultVehicleRaycaster>(&world);
    vehicle = std::make_unique<btRaycastVehicle>(tuning, chassis.get(), raycaster.get());
    vehicle->setCoordinateSystem(0, 1, 2);  // right = x, up = y, forward = z
    world.addVehicle(vehicle.get());
    const btVector3 down(0, -1, 0), axle(-1, 0, 0);
    const double hx = p.halfExtents.x() - 0.3 * p.wheelWidth, hz = p.halfExtents.z() - p.wheelRadius - 0.15;
    const double y = p.wheelConnectionHeight;
    const btVector3 points[4] = {{btScalar(hx), btScalar(y), btScalar(hz)},
                                 {btScalar(-hx), btScalar(y), btScalar(hz)},
                                 {btScalar(hx), btScalar(y), btScalar(-hz)},
                                 {btScalar(-hx), btScalar(y), btScalar(-hz)}};
    for (int i = 0; i < 4; ++i)
        vehicle->addWheel(points[i], down, axle, btScalar(p.suspensionRestLength),
                          btScalar(p.wheelRadius), tuning, /*isFrontWheel=*/i < 2);
    for (int i = 0; i < 4; ++i) {
        btWheelInfo& w = vehicle->getWheelInfo(i);
        w.m_suspensionStiffness = btScalar(p.suspensionStiffness);
        w.m_wheelsDampingRelaxation = btScalar(p.dampingRelaxation);
        w.m_wheelsDampingCompression = btScalar(p.dampingCompression);
        w.m_frictionSlip = btScalar(p.frictionSlip);
        w.m_rollInfluence = btScalar(p.rollInfluence);
    }
    vehicle->resetSuspension();
}

VehicleWorld::VehicleWorld(const VehicleParams& p) : impl_(std::make_unique<Impl>()), params_(p) {
    ++gWorlds;
    Impl& m = *impl_;
    m.world.setGravity(btVector3(0, -9.81f, 0));
    props_ = groundProps();
    m.addGround(props_);
    m.addChassis(p);
    m.addVehicle(p);
}

VehicleWorld::~VehicleWorld() = default;

void VehicleWorld::setControls(const VehicleControls& c) { impl_->controls = c; }

double VehicleWorld::stepTick(double dt) {
    Impl& m = *impl_;
    const VehicleControls& c = m.controls;
    // Steering follows the input at a limited rate, like a driver's hands.
    // Less lock at speed, as any driver (or driving game) does: full lock at 25 m/s rolls a car.
    const double lock = params_.maxSteer / (1 + speed() / params_.steerSpeedFalloff);
    const double target = std::clamp(c.steer, -1.0, 1.0) * lock;
    const double maxDelta = params_.steerRate * dt;
    m.steering += std::clamp(target - m.steering, -maxDelta, maxDelta);
    const double engine = std::clamp(c.throttle, -1.0, 1.0) * params_.engineForce;
    const double brake = std::clamp(c.brake, 0.0, 1.0) * params_.brakeForce;
    const double handbrake = std::clamp(c.handbrake, 0.0, 1.0) * params_.brakeForce * 2;
    for (int i = 0; i < 2; ++i) {
        m.vehicle->setSteeringValue(btScalar(m.steering), i);
        m.vehicle->applyEngineForce(0, i);
        m.vehicle->setBrake(btScalar(brake), i);
    }
    for (int i = 2; i < 4; ++i) {
        m.vehicle->applyEngineForce(btScalar(brake > 0 ? 0.0 : engine), i);
        m.vehicle->setBrake(btScalar(brake + handbrake), i);
    }
    const btScalar h = btScalar(dt);
    m.world.stepSimulation(h, 1, h);  // one internal tick of exactly h
    return double(h);
}

RigidPose VehicleWorld::chassis() const {
    const btRigidBody& b = *impl_->chassis;
    RigidPose p;
    const btTransform& t = b.getCenterOfMassTransform();
    const btQuaternion q = t.getRotation();
    p.position = eig(t.getOrigin());
    p.rotation = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).normalized();
    p.linearVelocity = eig(b.getLinearVelocity());
    p.angularVelocity = eig(b.getAngularVelocity());
    return p;
}

double VehicleWorld::speed() const {
    const Eigen::Vector3d v = eig(impl_->chassis->getLinearVelocity());
    return std::hypot(v.x(), v.z());
}

int VehicleWorld::wheelCount() const { return impl_->vehicle->getNumWheels(); }

Eigen::Isometry3d VehicleWorld::wheelTransform(int i) const {
    impl_->vehicle->updateWheelTransform(i, /*interpolatedTransform=*/false);
    return toIsometry(impl_->vehicle->getWheelInfo(i).m_worldTransform);
}

int VehicleWorld::worldsCreated() { return gWorlds.load(); }

void VehicleWorld::routeProfileZones(void (*enter)(const char*), void (*leave)()) {
    // Bullet calls these unconditionally: never leave them null, restore its own instead.
    static btEnterProfileZoneFunc* const bulletEnter = btGetCurrentEnterProfileZoneFunc();
    static btLeaveProfileZoneFunc* const bulletLeave = btGetCurrentLeaveProfileZoneFunc();
    btSetCustomEnterProfileZoneFunc(enter ? enter : bulletEnter);
    btSetCustomLeaveProfileZoneFunc(leave ? leave : bulletLeave);
}

}  // namespace engine
