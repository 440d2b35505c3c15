// What a reference run's cache entry is keyed by (reference_cache.h): the flag as the library
// steps it, its pole, the path sampled at every tick, and the code's version.

#include "reference_cache.h"

#include "cloth/cloth.h"
#include "cloth/flag_on_pole.h"
#include "engine/flag/flag.h"

#include <cstdio>
#include <sstream>

namespace study {

namespace {

// Numbers as the text that reads back to the same double.
std::string numbers(std::initializer_list<double> values) {
    std::string out;
    char b[32];
    for (double v : values) {
        std::snprintf(b, sizeof b, "%.17g ", v);
        out += b;
    }
    return out;
}

std::string vec(const Eigen::Vector3d& v) { return numbers({v.x(), v.y(), v.z()}); }

// The flag as cloth::Cloth is made of and stepped with (engine::flagDescOf, clothSettingsOf).
std::string flagKey(const engine::SceneConfig& s, const engine::PoleMount& mount) {
    const cloth::FlagDesc f = engine::flagDescOf(s);
    const cloth::ClothSettings c = engine::clothSettingsOf(s);
    std::ostringstream k;
    k << "flag " << f.nx << " " << f.ny << " " << numbers({f.width, f.height, f.mass}) << "\n";
    k << "stiffness " << numbers({f.stiffness.structural, f.stiffness.shear, f.stiffness.bend}) << "\n";
    k << "solver " << cloth::describe(c.solver) << "\nconstraints " << c.constraints.describe() << "\n";
    k << "environment " << vec(c.environment.gravity) << numbers({c.environment.drag}) << "\n";
    k << "air " << c.air << " " << c.implicitAir << " " << vec(c.airParams.wind)
      << numbers({c.airParams.density, c.airParams.dragCoefficient, c.airParams.liftCoefficient,
                  c.airParams.frictionCoefficient})
      << "\n";
    k << "collisions " << c.collisions << " " << numbers({c.thickness}) << "substeps " << c.substeps << " hz "
      << numbers({s.physicsHz}) << "\n";
    k << "contact " << c.contact.enabled << " " << c.contact.self << " " << numbers({c.contact.thickness, c.contact.maxMove});
    if (c.contact.substepStride != 1) k << "stride " << c.contact.substepStride << " ";  // (the defaults write nothing: the keys of earlier runs hold)
    if (c.contact.selfBounds == cloth::ContactSettings::SelfBounds::HalfSpaces) k << "half-spaces ";
    if (c.contact.strideMove != 0) k << "stride-move " << numbers({c.contact.strideMove});
    k << "sleeve " << f.onShell << "\n";
    k << "pole " << vec(mount.base) << numbers({mount.height, mount.radius}) << vec(mount.trailing) << "\n";
    return k.str();
}

// The path: its parameters, and a hash of its carrier at every tick (pose and velocity).
std::string pathKey(const Extreme& x, double physicsHz) {
    std::uint64_t h = fnv1a(nullptr, 0);
    const int ticks = int(std::floor(x.duration * physicsHz + 1e-9));
    for (int k = 0; k <= ticks; ++k) {
        const engine::RigidFrame c = x.carrier(k / physicsHz);
        const double v[13] = {c.position.x(), c.position.y(), c.position.z(), c.rotation.w(), c.rotation.x(),
                              c.rotation.y(), c.rotation.z(), c.linearVelocity.x(), c.linearVelocity.y(),
                              c.linearVelocity.z(), c.angularVelocity.x(), c.angularVelocity.y(), c.angularVelocity.z()};
        h = fnv1a(v, sizeof v, h);
    }
    char b[200];
    std::snprintf(b, sizeof b, "path %s %.17g %.17g %.17g %.17g %d carrier %016llx\n", x.name.c_str(), x.duration,
                  x.massScale, x.wind, x.jumpAt, int(x.flutter), static_cast<unsigned long long>(h));
    return b;
}

// A short, hard path: accelerating at 20 m/s^2 while turning at 3 rad/s, a jolt at 0.15 s.
Extreme versionPath() {
    return {"version", 0.25, [](double t) {
                engine::RigidFrame c;
                const double jolt = t > 0.15 ? 0.05 : 0;
                c.position = Eigen::Vector3d(jolt, 0, 10 * t * t);
                c.linearVelocity = Eigen::Vector3d(0, 0, 20 * t);
                c.rotation = Eigen::AngleAxisd(3 * t, Eigen::Vector3d::UnitY());
                c.angularVelocity = Eigen::Vector3d(0, 3, 0);
                return c;
            }, 1, 6, 0.15, true};
}

}  // namespace

std::string referenceKey(const engine::SceneConfig& s, const engine::PoleMount& mount, const Extreme& x,
                         bool keepStates, const std::string& codeVersion) {
    return "code " + codeVersion + "\n" + flagKey(s, mount) + pathKey(x, s.physicsHz) +
           "states " + (keepStates ? "kept" : "none") + "\n";
}

namespace {

// A run as the cache stores it, every state whole, into the hash h.
std::uint64_t hashOf(ExtremeRun r, std::uint64_t h) {
    r.msPerTick = 0;  // the clock's, not the code's
    for (const cloth::State& st : r.states) h = fnv1a(st.v.data(), st.v.size() * sizeof(double), fnv1a(st.x.data(), st.x.size() * sizeof(double), h));
    const double figures[] = {double(r.stable), double(r.failures), r.maxStretch, r.peakStretch, r.p99Stretch,
                              r.lateStretch, r.maxSpeed, r.energyMean, r.energyLate, r.patchEnergyLate[0],
                              r.patchEnergyLate[1], r.patchEnergyLate[2], r.iterationsMean, double(r.iterationsMax),
                              double(r.crossingsMax), double(r.crossingTicks)};
    h = fnv1a(figures, sizeof figures, h);
    return fnv1a(r.energyWindows.data(), r.energyWindows.size() * sizeof(double), h);
}

// Contact through a fold, which the version path's fine steps never make: the paper's step on a
// 17x17 flag with tethers, thrown 1 m by a teleport of its carrier after 10 ticks and stepped 2
// more, so that the broad phase's cones, the pairs, the pushes and the bounds all work (thousands
// of self pairs); its last state into the hash h.
std::uint64_t foldHash(std::uint64_t h) {
    engine::SceneConfig s;
    s.subsystems = engine::kCloth | engine::kAir | engine::kCollision;
    s.flag.nx = s.flag.ny = 17;
    s.flag.constraints.tether = 0.02, s.flag.constraints.stretchLimit = 0.1;
    s.flag.contact.enabled = s.flag.contact.self = true;
    const cloth::Pole pole;
    const auto carrier = [](int tick) {
        cloth::RigidFrame c;
        if (tick >= 10) c.position = Eigen::Vector3d(1, 0, 0);
        return c;
    };
    cloth::Cloth cloth(cloth::flagOnPole(engine::flagDescOf(s), pole, s.flag.thickness), engine::clothSettingsOf(s), carrier(0));
    for (int k = 1; k <= 12; ++k) cloth.step(1.0 / 240, carrier(k), {cloth::poleCollider(pole, carrier(k))});
    const cloth::State& st = cloth.state();
    return fnv1a(st.v.data(), st.v.size() * sizeof(double), fnv1a(st.x.data(), st.x.size() * sizeof(double), h));
}

}  // namespace

// The small flag's reference through the version path, without contact and with it, and contact
// through a fold.
const std::string& integratorVersion() {
    static const std::string version = [] {
        engine::SceneConfig s;
        s.subsystems = engine::kCloth | engine::kAir | engine::kCollision;
        s.flag.nx = 9, s.flag.ny = 7;
        s.flag.constraints.tether = 0.02, s.flag.constraints.stretchLimit = 0.1;
        const Extreme x = versionPath();
        s.air.wind = Eigen::Vector3d(x.wind, 0, 0);
        std::uint64_t h = hashOf(runExtreme(referenceScene(s, 8), engine::PoleMount{}, x, true), fnv1a(nullptr, 0));
        s.flag.contact.enabled = true;
        h = foldHash(hashOf(runExtreme(referenceScene(s, 8), engine::PoleMount{}, x, true), h));
        char b[20];
        std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
        return std::string(b);
    }();
    return version;
}

}  // namespace study
