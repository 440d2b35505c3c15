#include "cloth/flag_on_pole.h"

#include "cloth/presets.h"

#include <cmath>

namespace cloth {

Model flagModel(const FlagDesc& flag, const Pole& pole, Scalar thickness) {
    GridDesc g;
    g.nx = flag.nx;
    g.ny = flag.ny;
    g.width = flag.width;
    g.height = flag.height;
    g.totalMass = flag.mass;
    g.stiffness = flag.stiffness;
    g.origin = pole.base + Vec3(0, pole.height, 0) + (flag.onShell ? pole.radius + thickness : 0) * pole.trailing;
    g.axisU = pole.trailing;
    g.axisV = -Vec3::UnitY();
    return Model::fromGrid(g);
}

namespace {

// The rest shape with a millimetre ripple across the flag's plane, the same every time.
Points rippled(const Model& model, const Pole& pole) {
    Points start = model.restPositions();
    const Vec3 across = pole.trailing.cross(Vec3::UnitY());
    const int nx = model.gridNx();
    for (Index i = 0; i < model.particleCount(); ++i) {
        const Scalar u = Scalar(i % nx) / (nx - 1), v = Scalar(i / nx) / (model.gridNy() - 1);
        start.col(i) = model.restPositions().col(i) + 0.003 * u * std::sin(3.0 * u + 2.0 * v) * across;
    }
    return start;
}

}  // namespace

ClothDesc flagOnPole(const FlagDesc& flag, const Pole& pole, Scalar thickness) {
    ClothDesc d{flagModel(flag, pole, thickness), {}, {}, {}, {poleSolid(pole)}};
    for (const Pin& p : pinColumn(d.model)) d.attachments.push_back({p.particle, p.x});
    d.start = rippled(d.model, pole);
    d.collisionSkip.assign(std::size_t(d.model.particleCount()), 0);
    const Scalar sleeve = pole.radius + thickness;
    for (Index i = 0; i < d.model.particleCount(); ++i) {
        const Vec3 r = d.model.restPositions().col(i) - pole.base;
        if (std::hypot(r.x(), r.z()) < sleeve) d.collisionSkip[std::size_t(i)] = 1;
    }
    return d;
}

std::pair<Vec3, Vec3> poleAxis(const Pole& pole) {
    return {pole.base, pole.base + Vec3(0, pole.height - pole.radius, 0)};
}

Collider poleSolid(const Pole& pole) {
    const auto [a, b] = poleAxis(pole);
    Collider c;
    c.shape = Collider::Shape::Capsule;
    c.axis = Vec3::UnitY();
    c.center = 0.5 * (a + b);
    c.halfExtents = Vec3(0.5 * (b - a).norm(), 0, 0);
    c.radius = pole.radius;
    return c;
}

Collider poleCollider(const Pole& pole, const RigidFrame& carrier) {
    Collider c;
    c.shape = Collider::Shape::Capsule;
    c.axis = carrier.rotation * Vec3::UnitY();
    c.center = carrier.point(pole.base + Vec3(0, pole.height / 2, 0));
    c.halfExtents = Vec3(pole.height / 2, 0, 0);
    c.radius = pole.radius;
    c.velocity = carrier.velocityAt(c.center);
    return c;
}

}  // namespace cloth
