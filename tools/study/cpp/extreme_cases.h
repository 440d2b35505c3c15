#pragma once
// The study's extreme cases for the demo's flag (part 2 of tools/study/cpp/cloth_study.cpp): each a
// carrier motion of the pole (pose and velocity over time), a mass scale and a wind; and the
// guard that every case drives the flag: a case whose carrier moves no pin and that has no wind
// would pass with any solver, because nothing happens to the flag.

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/flag/flag.h"
#include "engine/scene/scene.h"

namespace study {

struct Extreme {
    std::string name;
    double duration;
    std::function<engine::RigidFrame(double)> carrier;  // pose and velocity at time t
    double massScale = 1, wind = 0;
    double jumpAt = -1;  // a discontinuity of the pole (teleport): peak_stretch leaves out 0.25 s after it
    bool flutter = false;  // the air keeps the flag fluttering to the end: its energy is judged too
};

// The spin's vertical axis passes through this point of the carrier frame (the pole's base is
// the frame's origin): 1.6 m ahead of the pole, where the demo's chassis origin is (the demo's
// vehicle carries the pole at pole_offset (0, 0.85, -1.6), 1.6 m behind its origin; +z is
// forward). The carrier turns like the demo's vehicle doing donuts: the pole circles the axis at
// 1.6 m, and the flag, trailing along -z, points away from it.
const Eigen::Vector3d kSpinAxisPoint(0, 0, 1.6);

// The carrier turned by `angle` about the vertical through `axisPoint` (a carrier-frame point,
// fixed in the world where it is at angle 0), turning at `rate` rad/s.
engine::RigidFrame turnedAbout(const Eigen::Vector3d& axisPoint, double angle, double rate);

// The six cases, in the study's order: speed_50mps, stop_10g, spin_5radps, teleport_1m,
// light_particles, gale_40mps (the first and the last flutter).
std::vector<Extreme> extremes();

// The teleport case with a jump of `metres` (teleport_1m is teleport(1)): the pole jumps that far
// along +x at t = 0.5 s, without a velocity. Its name is teleportName(metres), e.g. teleport_0.9m.
Extreme teleport(double metres);
std::string teleportName(double metres);

// The study's flag from a scene: contact only when asked, and then all of it (the pole, the body
// and the flag itself), whatever contact the scene ships with.
engine::SceneConfig withContact(engine::SceneConfig scene, bool contact);

// The demo's flag in case x at another resolution: same size, mass and stiffness, same aspect;
// the case's mass scale and wind.
engine::SceneConfig extremeScene(const engine::SceneConfig& demo, const Extreme& x, int size);

// The pole of the extreme cases: at the carrier's origin, as tall as the demo's.
engine::PoleMount extremeMount(const engine::SceneConfig& demo);

// The flag's pinned column (the pole edge) in the carrier frame, for the scene's flag on `mount`.
std::vector<Eigen::Vector3d> pinnedColumn(const engine::SceneConfig& scene, const engine::PoleMount& mount);

// How hard a carrier drives the pins: the largest speed and acceleration of any pin, sampled at
// t = k h for every tick k of the duration. Speed: the larger of the pin's velocity (the carrier's
// velocity at the pin) and its displacement over the last tick / h; acceleration: the larger of the
// change of that velocity / h and the second difference of its position / h^2 (a teleport moves
// the pins without giving them a velocity).
struct PinMotion {
    double speedMax = 0, accelMax = 0;
};
PinMotion pinMotion(const std::function<engine::RigidFrame(double)>& carrier, double duration, double h,
                    const std::vector<Eigen::Vector3d>& pins);

// Below both of these a case moves no pin.
constexpr double kIdleSpeed = 1e-6;  // m/s
constexpr double kIdleAccel = 1e-6;  // m/s^2

struct CaseMotion {
    std::string name;
    PinMotion pins;
    double wind = 0;
    bool drivesTheFlag() const { return pins.speedMax >= kIdleSpeed || pins.accelMax >= kIdleAccel || wind != 0; }
};

// Every case's pin motion on the demo's flag and mount, at the demo's physics rate.
std::vector<CaseMotion> caseMotions(const engine::SceneConfig& demo, const std::vector<Extreme>& cases);

// Why the cases fail the guard (one line per case that moves no pin and has no wind), or empty.
std::string idleCases(const std::vector<CaseMotion>& motions);

}  // namespace study
