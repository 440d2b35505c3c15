#pragma once
// Triangle mesh data as loaded from assets or generated, in the form the renderer uploads.

#include <cstdint>
#include <string>
#include <vector>

namespace engine {

struct MeshData {
    std::vector<float> positions;  // x, y, z per vertex
    std::vector<float> normals;    // x, y, z per vertex (may be empty: flat normals computed)
    std::vector<float> uvs;        // u, v per vertex (may be empty)
    std::vector<std::uint32_t> indices;  // three per triangle
    float color[3] = {0.7f, 0.7f, 0.7f}; // base colour (from the material, when any)
    std::size_t vertexCount() const { return positions.size() / 3; }
    std::size_t triangleCount() const { return indices.size() / 3; }
};

}  // namespace engine
