#pragma once
// Simple generated meshes: boxes, cylinders, ground planes. No dependencies.

#include "engine/mesh.h"

namespace engine {

// Axis-aligned box centred at the origin, with per-face normals and uvs.
MeshData makeBox(float hx, float hy, float hz);
// Cylinder along +y centred at the origin (caps included), smooth sides.
MeshData makeCylinder(float radius, float halfHeight, int segments);
// A square in the x-z plane at y = 0, `size` across, uvs repeating every `tile` metres.
MeshData makeGround(float size, float tile);

}  // namespace engine
