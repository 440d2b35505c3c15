#include "engine/assets/primitives.h"

#include <cmath>

namespace engine {

namespace {

void addVertex(MeshData& m, float x, float y, float z, float nx, float ny, float nz, float u, float v) {
    m.positions.insert(m.positions.end(), {x, y, z});
    m.normals.insert(m.normals.end(), {nx, ny, nz});
    m.uvs.insert(m.uvs.end(), {u, v});
}

// A quad from four corners (counter-clockwise seen from the normal's side).
void addQuad(MeshData& m, const float (&c)[4][3], const float (&n)[3]) {
    const auto base = static_cast<std::uint32_t>(m.vertexCount());
    const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int i = 0; i < 4; ++i) addVertex(m, c[i][0], c[i][1], c[i][2], n[0], n[1], n[2], uv[i][0], uv[i][1]);
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

}  // namespace

MeshData makeBox(float hx, float hy, float hz) {
    MeshData m;
    // +x, -x, +y, -y, +z, -z faces.
    addQuad(m, {{hx, -hy, hz}, {hx, -hy, -hz}, {hx, hy, -hz}, {hx, hy, hz}}, {1, 0, 0});
    addQuad(m, {{-hx, -hy, -hz}, {-hx, -hy, hz}, {-hx, hy, hz}, {-hx, hy, -hz}}, {-1, 0, 0});
    addQuad(m, {{-hx, hy, hz}, {hx, hy, hz}, {hx, hy, -hz}, {-hx, hy, -hz}}, {0, 1, 0});
    addQuad(m, {{-hx, -hy, -hz}, {hx, -hy, -hz}, {hx, -hy, hz}, {-hx, -hy, hz}}, {0, -1, 0});
    addQuad(m, {{-hx, -hy, hz}, {hx, -hy, hz}, {hx, hy, hz}, {-hx, hy, hz}}, {0, 0, 1});
    addQuad(m, {{hx, -hy, -hz}, {-hx, -hy, -hz}, {-hx, hy, -hz}, {hx, hy, -hz}}, {0, 0, -1});
    return m;
}

MeshData makeCylinder(float radius, float halfHeight, int segments) {
    MeshData m;
    const float twoPi = 6.28318530718f;
    // Sides: two rings with outward normals.
    for (int i = 0; i <= segments; ++i) {
        const float a = twoPi * i / segments, c = std::cos(a), s = std::sin(a);
        addVertex(m, radius * c, -halfHeight, radius * s, c, 0, s, float(i) / segments, 0);
        addVertex(m, radius * c, halfHeight, radius * s, c, 0, s, float(i) / segments, 1);
    }
    for (int i = 0; i < segments; ++i) {
        const auto b = static_cast<std::uint32_t>(2 * i);
        m.indices.insert(m.indices.end(), {b, b + 1, b + 3, b, b + 3, b + 2});
    }
    // Caps: a centre vertex and a ring each.
    for (int cap = 0; cap < 2; ++cap) {
        const float y = cap ? halfHeight : -halfHeight, ny = cap ? 1.f : -1.f;
        const auto centre = static_cast<std::uint32_t>(m.vertexCount());
        addVertex(m, 0, y, 0, 0, ny, 0, 0.5f, 0.5f);
        for (int i = 0; i <= segments; ++i) {
            const float a = twoPi * i / segments, c = std::cos(a), s = std::sin(a);
            addVertex(m, radius * c, y, radius * s, 0, ny, 0, 0.5f + 0.5f * c, 0.5f + 0.5f * s);
        }
        for (int i = 0; i < segments; ++i) {
            const std::uint32_t a = centre + 1 + i, b = a + 1;
            if (cap) m.indices.insert(m.indices.end(), {centre, b, a});
            else m.indices.insert(m.indices.end(), {centre, a, b});
        }
    }
    return m;
}

MeshData makeGround(float size, float tile) {
    MeshData m;
    const float h = size / 2, r = size / tile;
    addVertex(m, -h, 0, -h, 0, 1, 0, 0, 0);
    addVertex(m, -h, 0, h, 0, 1, 0, 0, r);
    addVertex(m, h, 0, h, 0, 1, 0, r, r);
    addVertex(m, h, 0, -h, 0, 1, 0, r, 0);
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

}  // namespace engine
