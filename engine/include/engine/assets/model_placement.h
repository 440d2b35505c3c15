#pragma once
// How a scene places its vehicle model on the chassis, before the chassis pose: the model's up
// axis and heading, then the fit onto the chassis box (uniform scale, centred, then seated on the
// box's underside), then a scale and an offset of the scene's own. The defaults place a +y-up,
// +z-forward model exactly as the fit alone.

#include <array>

namespace engine {

struct ModelPlacement {
    char up = 'y';                       // the model's up axis: 'y', or 'z' (z-up tools)
    double yawDegrees = 0;               // then a turn about the vertical (the model's forward onto +z)
    double scale = 1;                    // after the fit, about the chassis centre
    std::array<double, 3> offset = {0, 0, 0};  // after the scale, in the chassis frame (m)
};

}  // namespace engine
