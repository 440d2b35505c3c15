#pragma once
// A flag on a pole: a grid cloth whose first column is attached along a pole standing on a
// carrier (a vehicle, or the world). Everything here is in the carrier's frame, the pole along
// its +y axis; the flag trails from the pole along `trailing`.

#include <utility>

#include "cloth/cloth.h"

namespace cloth {

struct Pole {
    Vec3 base = Vec3::Zero();   // the foot of its axis
    Scalar height = 3.0;        // m
    Scalar radius = 0.03;       // m
    Vec3 trailing = -Vec3::UnitZ();  // unit, perpendicular to +y: where the flag streams at rest
};

struct FlagDesc {
    int nx = 33, ny = 33;  // particles across (from the pole) and down
    Scalar width = 1.5, height = 1.0;
    Scalar mass = 0.25;  // kg
    Stiffness stiffness = {1e3, 1e2, 5};
    // Column 0 on the pole's collision shell (radius + thickness from its axis, on the trailing
    // side), like a sleeve sewn round it: no edge from the pinned column runs through the pole and
    // no free particle starts inside the shell, at any resolution (what contact needs); false: on
    // the pole's axis.
    bool onShell = false;
};

// The flag's grid: column 0 down the pole from its top (on its axis, or on its collision shell:
// FlagDesc::onShell), the flag trailing behind. Throws std::invalid_argument naming the field for
// a grid that cannot be built.
Model flagModel(const FlagDesc& flag, const Pole& pole, Scalar thickness);

// The flag as a Cloth is made: its model, column 0 attached where it rests on the pole,
// its start shape (the rest shape with a millimetre ripple across its plane: no real flag is
// perfectly flat, and a flat sheet pinned along an edge is an unstable equilibrium it would never
// leave), and the particles the colliders leave alone: those whose rest position lies inside
// the pole's collision capsule (radius + thickness), and the pole as a solid its carrier holds
// (contact.h).
ClothDesc flagOnPole(const FlagDesc& flag, const Pole& pole, Scalar thickness);

// The pole's solid, in its carrier's frame: a capsule of the pole's radius whose rounded top is the
// pole's top, its axis segment from the base to the top less the radius (poleAxis gives its
// ends). Contact keeps the cloth out of it and the crossing checker judges edges against it. The
// flag's top pins, on the collision shell at the pole's top, lie outside it; a capsule over the
// whole pole would stand a radius above its top, and contact pushed the flag's top row onto that
// cap and over it, 17 cm above the pole at rest.
std::pair<Vec3, Vec3> poleAxis(const Pole& pole);
Collider poleSolid(const Pole& pole);

// The pole as a collider for the particle collisions, in world space for the carrier's pose: a
// capsule along the whole pole.
Collider poleCollider(const Pole& pole, const RigidFrame& carrier);

}  // namespace cloth
