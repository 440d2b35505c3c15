#pragma once
// One OpenGL 3.3 core renderer for the headless (OSMesa) and the window (SDL2) context: a sky
// gradient, a sun with a shadow map (3x3 PCF), hemisphere ambient light, textured meshes, and a
// double-sided dynamic mesh for the flag whose positions and smooth normals change every frame.

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "engine/mesh.h"
#include "engine/scene/anti_aliasing.h"
#include "engine/render/gl_context.h"

namespace engine {

struct Material {
    Eigen::Vector3f color = {0.8f, 0.8f, 0.8f};
    int texture = -1;          // from addTexture, or -1
    bool doubleSided = false;  // light back faces with the flipped normal
};

struct Camera {
    Eigen::Vector3f eye = {0, 2, 8}, target = {0, 1, 0}, up = {0, 1, 0};
    float fovY = 50;  // degrees
    float nearPlane = 0.1f, farPlane = 500;
};

struct Lighting {
    Eigen::Vector3f sunDirection = Eigen::Vector3f(-0.45f, -0.8f, -0.35f).normalized();  // travel direction of light
    Eigen::Vector3f sunColor = {1.0f, 0.96f, 0.88f};
    Eigen::Vector3f skyColor = {0.42f, 0.62f, 0.9f}, horizonColor = {0.82f, 0.88f, 0.95f};
    Eigen::Vector3f groundBounce = {0.35f, 0.32f, 0.28f};
    float ambient = 0.35f;
    Eigen::Vector3f shadowFocus = Eigen::Vector3f::Zero();  // the shadow map covers this point
    float shadowExtent = 25;                                // half size of the covered square, m
};

struct DrawItem {
    int mesh = -1;
    Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
    bool castsShadow = true;  // the ground receives shadows but need not cast any
};

class Renderer {
public:
    // The context must be current. Throws std::runtime_error when GL functions are missing or a
    // shader does not compile (the message carries the compiler's log).
    // Msaa: the main pass has msaaSamples samples (clamped to what the context offers; none, with
    // a note, when it offers none; none when msaaSamples < 2).
    Renderer(GLContext& context, int shadowMapSize, AntiAliasing aa = AntiAliasing::Off, int msaaSamples = 4);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    int addTexture(const std::vector<std::uint8_t>& rgba, int width, int height);
    int addMesh(const MeshData& mesh, const Material& material);
    // A mesh whose positions and normals are replaced each frame (same topology and uvs).
    int addDynamicMesh(std::size_t vertexCount, const std::vector<std::uint32_t>& indices,
                       const std::vector<float>& uvs, const Material& material);
    void updateDynamicMesh(int mesh, const std::vector<float>& positions, const std::vector<float>& normals);

    void render(const Camera& camera, const Lighting& lighting, const std::vector<DrawItem>& items);
    // What runs (Auto resolved): Off, Msaa or Post (the main pass as with Off; the caller runs the
    // pass over the frame it reads back, frame_aa.h); and the context's GL_RENDERER.
    AntiAliasing antiAliasing() const;
    const std::string& glRenderer() const;
    // The frame just rendered, RGBA8, rows top-down.
    void readPixels(std::vector<std::uint8_t>& rgba);
    // A frame in that form (the post pass's) drawn over framebuffer 0: a window shows it.
    void showPixels(const std::vector<std::uint8_t>& rgba);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Area-weighted vertex normals of a triangle mesh (positions xyz, three indices per triangle).
void computeSmoothNormals(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices,
                          std::vector<float>& normals);

// Deterministic procedural textures (RGBA8).
std::vector<std::uint8_t> makeGroundTexture(int size);
std::vector<std::uint8_t> makeFlagTexture(int width, int height);

}  // namespace engine
