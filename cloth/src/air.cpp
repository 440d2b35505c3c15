#include "cloth/air.h"

#include <cmath>

namespace cloth {

void addAirForces(const Model& model, const State& state, const AirParams& air, Points& f) {
    const Scalar halfRho = Scalar(0.5) * air.density;
    for (const Triangle& t : model.triangles()) {
        const Vec3 a = state.x.col(t[0]), b = state.x.col(t[1]), c = state.x.col(t[2]);
        const Vec3 cross = (b - a).cross(c - a);
        const Scalar twiceArea = cross.norm();
        if (twiceArea < 1e-14) continue;
        const Scalar area = Scalar(0.5) * twiceArea;
        Vec3 n = cross / twiceArea;
        const Vec3 w = air.wind - (state.v.col(t[0]) + state.v.col(t[1]) + state.v.col(t[2])) / 3;
        const Scalar speed = w.norm();
        if (speed < 1e-9) continue;
        Scalar wn = w.dot(n);
        if (wn < 0) {  // orient n with the flow: the force formulas below assume w . n >= 0
            n = -n;
            wn = -wn;
        }
        const Vec3 tangential = w - wn * n;
        Vec3 force = halfRho * area * speed *
                     (air.dragCoefficient * wn * n + air.frictionCoefficient * tangential);
        // Lift: perpendicular to w in the plane of w and n; cos(theta) sin(theta) |w|^2 with
        // theta the angle of attack (between w and the cloth's plane).
        const Vec3 liftDir = n - (wn / (speed * speed)) * w;
        const Scalar liftNorm = liftDir.norm();
        if (liftNorm > 1e-9) {
            const Scalar sinA = wn / speed, cosA = tangential.norm() / speed;
            force += halfRho * area * air.liftCoefficient * speed * speed * sinA * cosA *
                     (liftDir / liftNorm);
        }
        const Vec3 share = force / 3;
        f.col(t[0]) += share;
        f.col(t[1]) += share;
        f.col(t[2]) += share;
    }
}

}  // namespace cloth
