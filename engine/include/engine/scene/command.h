#pragma once
// A change to a running scene: what the live panel's widgets do and what a script's events say.
// Every panel action is a Command, applied at the start of a frame and recorded with that
// frame's index (--record-input), so a live session replays to identical frames (--script).
//
//   name         value                      what it changes
//   solver       a solver spec              the flag's solver, e.g. multigrid:cycles=2
//   stretch      N/m, > 0                   structural spring stiffness
//   shear        N/m, > 0                   shear spring stiffness
//   bend         N/m, > 0                   bend spring stiffness
//   mass         kg, > 0                    the flag's total mass
//   wind         x,y,z m/s, each |.| <= 100 the wind, world frame
//   air_density  kg/m^3 in [0, 100]         the air's density
//   physics_hz   ticks per second [30, 4000] the fixed tick (Bullet and the cloth)
//   camera       yaw,pitch,zoom             the chase camera's orbit: degrees about the vehicle
//                                           (|yaw| <= 180), degrees up (|pitch| <= 80), distance
//                                           factor in [0.2, 5]
//   pause        on | off                   stop or resume the simulation (frames still render)
//   step         (none)                     one tick while paused
//   reset        (none)                     the flag back to rest on its pole
// The flag keeps its state through a change of solver, stiffness, mass or air.

#include <string>
#include <vector>

namespace engine {

struct Command {
    std::string name;
    std::string value;  // empty for step and reset
    bool operator==(const Command&) const = default;
};

// Empty when the command is valid, else why not (naming the command and the value).
std::string checkCommand(const Command& command);

// The table above, one line per command, for --help and the README.
std::string commandHelp();

// The parsed values (call only on a command checkCommand accepted).
double commandNumber(const Command& command);
std::vector<double> commandVector(const Command& command);  // wind

}  // namespace engine
