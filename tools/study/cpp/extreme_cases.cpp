#include "extreme_cases.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

namespace study {

using engine::RigidFrame;
using Vec3 = Eigen::Vector3d;

RigidFrame turnedAbout(const Vec3& axisPoint, double angle, double rate) {
    RigidFrame c;
    c.rotation = Eigen::AngleAxisd(angle, Vec3::UnitY());
    c.position = axisPoint - c.rotation * axisPoint;  // so that c.point(axisPoint) == axisPoint
    c.angularVelocity = Vec3(0, rate, 0);
    c.linearVelocity = c.angularVelocity.cross(c.position - axisPoint);
    return c;
}

namespace {

// Straight-line cases: 0 -> 50 m/s in 2 s then cruise, and a 10 g stop from 30 m/s.
void addSpeedCases(std::vector<Extreme>& e) {
    e.push_back({"speed_50mps", 4, [](double t) {  // 0 -> 50 m/s in 2 s, then cruise
                     RigidFrame c;
                     const double a = 25, v = std::min(t, 2.0) * a;
                     const double x = t < 2 ? 0.5 * a * t * t : 50 + 50 * (t - 2);
                     c.position = Vec3(0, 0, x);
                     c.linearVelocity = Vec3(0, 0, v);
                     return c;
                 }, 1, 0, -1, true});
    e.push_back({"stop_10g", 3, [](double t) {  // cruise at 30 m/s, stop at 10 g at t = 1.5 s
                     RigidFrame c;
                     const double a = 98.1, t0 = 1.5, stopT = 30 / a;
                     double v = 30, x = 30 * t;
                     if (t > t0) {
                         const double s = std::min(t - t0, stopT);
                         v = 30 - a * s;
                         x = 30 * t0 + 30 * s - 0.5 * a * s * s;
                     }
                     c.position = Vec3(0, 0, x);
                     c.linearVelocity = Vec3(0, 0, v);
                     return c;
                 }});
}

}  // namespace

std::string teleportName(double metres) {
    std::ostringstream name;
    name << "teleport_" << metres << "m";
    return name.str();
}

Extreme teleport(double metres) {
    return {teleportName(metres), 2, [metres](double t) {  // the pole jumps sideways in one step at 0.5 s
                RigidFrame c;
                if (t >= 0.5) c.position = Vec3(metres, 0, 0);
                return c;
            }, 1, 0, 0.5};
}

std::vector<Extreme> extremes() {
    std::vector<Extreme> e;
    addSpeedCases(e);
    // A turn about the vertical through kSpinAxisPoint (1.6 m from the pole), up to 5 rad/s in 0.5 s.
    e.push_back({"spin_5radps", 3, [](double t) {
                     const double w = 5 * std::min(t / 0.5, 1.0);
                     const double angle = t < 0.5 ? 5 * t * t : 1.25 + 5 * (t - 0.5);
                     return turnedAbout(kSpinAxisPoint, angle, w);
                 }});
    e.push_back(teleport(1));
    e.push_back({"light_particles", 3, [](double t) {  // 1/100 of the mass, driven at 20 m/s
                     RigidFrame c;
                     c.position = Vec3(0, 0, 20 * t);
                     c.linearVelocity = Vec3(0, 0, 20);
                     return c;
                 }, 0.01});
    e.push_back({"gale_40mps", 3, [](double) { return RigidFrame{}; }, 1, 40, -1, true});
    return e;
}

engine::SceneConfig withContact(engine::SceneConfig scene, bool contact) {
    scene.flag.contact = cloth::ContactSettings{};
    scene.flag.contact.enabled = contact;
    return scene;
}

engine::SceneConfig extremeScene(const engine::SceneConfig& demo, const Extreme& x, int size) {
    engine::SceneConfig s = demo;
    s.flag.ny = int(std::lround(1 + (size - 1) * double(demo.flag.ny - 1) / (demo.flag.nx - 1)));
    s.flag.nx = size;
    s.flag.mass *= x.massScale;
    s.air.wind = Vec3(x.wind, 0, 0);
    return s;
}

engine::PoleMount extremeMount(const engine::SceneConfig& demo) {
    engine::PoleMount mount;
    mount.base = Vec3(0, 0, 0);
    mount.height = demo.vehicle.poleHeight;
    return mount;
}

std::vector<Vec3> pinnedColumn(const engine::SceneConfig& scene, const engine::PoleMount& mount) {
    const engine::Flag flag(scene, mount, RigidFrame{});  // identity carrier: world = carrier frame
    std::vector<Vec3> column;
    for (const cloth::Pin& p : flag.pins()) column.push_back(p.x);
    return column;
}

PinMotion pinMotion(const std::function<RigidFrame(double)>& carrier, double duration, double h,
                    const std::vector<Vec3>& pins) {
    std::vector<RigidFrame> frames;  // the ticks' carrier poses, as the study samples them
    for (int k = 0; k * h <= duration + 1e-9; ++k) frames.push_back(carrier(k * h));
    PinMotion m;
    for (const Vec3& local : pins) {
        auto x = [&](std::size_t k) { return frames[k].point(local); };
        auto v = [&](std::size_t k) { return frames[k].velocityAt(x(k)); };
        for (std::size_t k = 0; k < frames.size(); ++k) {
            m.speedMax = std::max(m.speedMax, v(k).norm());
            if (k == 0) continue;
            m.speedMax = std::max(m.speedMax, (x(k) - x(k - 1)).norm() / h);
            m.accelMax = std::max(m.accelMax, (v(k) - v(k - 1)).norm() / h);
            if (k + 1 < frames.size())
                m.accelMax = std::max(m.accelMax, (x(k + 1) - 2 * x(k) + x(k - 1)).norm() / (h * h));
        }
    }
    return m;
}

std::vector<CaseMotion> caseMotions(const engine::SceneConfig& demo, const std::vector<Extreme>& cases) {
    const engine::PoleMount mount = extremeMount(demo);
    const std::vector<Vec3> pins = pinnedColumn(demo, mount);
    std::vector<CaseMotion> motions;
    for (const Extreme& x : cases)
        motions.push_back({x.name, pinMotion(x.carrier, x.duration, 1.0 / demo.physicsHz, pins), x.wind});
    return motions;
}

std::string idleCases(const std::vector<CaseMotion>& motions) {
    std::ostringstream why;
    for (const CaseMotion& c : motions)
        if (!c.drivesTheFlag())
            why << "extreme case '" << c.name << "' moves no pin (largest pin speed " << c.pins.speedMax
                << " m/s, acceleration " << c.pins.accelMax << " m/s^2) and has no wind: every solver passes it\n";
    return why.str();
}

}  // namespace study
