#include "engine/assets/model_loader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>

#include "engine/scene/config_error.h"

namespace engine {

LoadedModel loadModel(const std::string& path, const ModelLimits& limits) {
    std::error_code ec;  // the non-throwing overload: a hostile path (too long, ...) is an error, not a crash
    if (!std::filesystem::is_regular_file(path, ec))
        throw ConfigError(path + ": model file not found" + (ec ? " (" + ec.message() + ")" : ""));
    Assimp::Importer importer;
    // Node transforms baked into vertices; data structure validated before we touch it.
    const unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices |
                           aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                           aiProcess_ValidateDataStructure | aiProcess_SortByPType |
                           aiProcess_FindInvalidData;
    const aiScene* scene = importer.ReadFile(path, flags);
    if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
        throw ConfigError(path + ": cannot read model: " + importer.GetErrorString());
    LoadedModel out;
    std::size_t vertices = 0, triangles = 0;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
        const aiMesh* m = scene->mMeshes[mi];
        if (!m || !(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !m->mVertices) continue;
        vertices += m->mNumVertices;
        triangles += m->mNumFaces;
        if (vertices > limits.maxVertices || triangles > limits.maxTriangles)
            throw ConfigError(path + ": model too large (" + std::to_string(vertices) + " vertices, " +
                              std::to_string(triangles) + " triangles; limit " +
                              std::to_string(limits.maxVertices) + " / " + std::to_string(limits.maxTriangles) + ")");
        MeshData part;
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
            const aiVector3D& p = m->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw ConfigError(path + ": mesh " + std::to_string(mi) + " vertex " + std::to_string(v) +
                                  " has a non-finite position");
            part.positions.insert(part.positions.end(), {p.x, p.y, p.z});
            const float c[3] = {p.x, p.y, p.z};
            for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
            if (m->mNormals && std::isfinite(m->mNormals[v].x) && std::isfinite(m->mNormals[v].y) &&
                std::isfinite(m->mNormals[v].z))
                part.normals.insert(part.normals.end(), {m->mNormals[v].x, m->mNormals[v].y, m->mNormals[v].z});
            if (m->mTextureCoords[0])
                part.uvs.insert(part.uvs.end(), {m->mTextureCoords[0][v].x, m->mTextureCoords[0][v].y});
        }
        if (part.normals.size() != part.positions.size()) part.normals.clear();
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const aiFace& face = m->mFaces[f];
            if (face.mNumIndices != 3) {
                ++out.droppedTriangles;
                continue;
            }
            const unsigned* i = face.mIndices;
            if (i[0] >= m->mNumVertices || i[1] >= m->mNumVertices || i[2] >= m->mNumVertices)
                throw ConfigError(path + ": mesh " + std::to_string(mi) + " face " + std::to_string(f) +
                                  " has an index out of range");
            const aiVector3D e1 = m->mVertices[i[1]] - m->mVertices[i[0]], e2 = m->mVertices[i[2]] - m->mVertices[i[0]];
            if ((e1 ^ e2).SquareLength() <= 1e-20f) {  // degenerate: no area, no normal
                ++out.droppedTriangles;
                continue;
            }
            part.indices.insert(part.indices.end(), {i[0], i[1], i[2]});
        }
        if (part.indices.empty()) continue;
        if (scene->mMaterials && m->mMaterialIndex < scene->mNumMaterials) {
            aiColor4D c;
            if (scene->mMaterials[m->mMaterialIndex]->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS &&
                std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) {
                part.color[0] = std::clamp(c.r, 0.f, 1.f);
                part.color[1] = std::clamp(c.g, 0.f, 1.f);
                part.color[2] = std::clamp(c.b, 0.f, 1.f);
            }
        }
        out.parts.push_back(std::move(part));
    }
    if (out.parts.empty()) throw ConfigError(path + ": model has no triangles");
    for (int k = 0; k < 3; ++k) out.boundsMin[k] = lo[k], out.boundsMax[k] = hi[k];
    return out;
}

void fitModel(LoadedModel& model, const float half[3]) {
    float centre[3], scale = INFINITY;
    for (int k = 0; k < 3; ++k) {
        centre[k] = 0.5f * (model.boundsMin[k] + model.boundsMax[k]);
        const float extent = 0.5f * (model.boundsMax[k] - model.boundsMin[k]);
        if (extent > 1e-9f) scale = std::min(scale, half[k] / extent);
    }
    if (!std::isfinite(scale)) scale = 1;
    for (MeshData& part : model.parts)
        for (std::size_t i = 0; i < part.positions.size(); ++i)
            part.positions[i] = (part.positions[i] - centre[i % 3]) * scale;
    for (int k = 0; k < 3; ++k) {
        model.boundsMin[k] = (model.boundsMin[k] - centre[k]) * scale;
        model.boundsMax[k] = (model.boundsMax[k] - centre[k]) * scale;
    }
}

namespace {

// The bounds of the parts' positions.
void updateBounds(LoadedModel& model) {
    for (int k = 0; k < 3; ++k) model.boundsMin[k] = INFINITY, model.boundsMax[k] = -INFINITY;
    for (const MeshData& part : model.parts)
        for (std::size_t i = 0; i < part.positions.size(); ++i) {
            model.boundsMin[i % 3] = std::min(model.boundsMin[i % 3], part.positions[i]);
            model.boundsMax[i % 3] = std::max(model.boundsMax[i % 3], part.positions[i]);
        }
}

// v := R v for every position and normal, R row-major.
void rotate(LoadedModel& model, const double R[9]) {
    for (MeshData& part : model.parts)
        for (std::vector<float>* v : {&part.positions, &part.normals})
            for (std::size_t i = 0; i + 2 < v->size(); i += 3) {
                const double x = (*v)[i], y = (*v)[i + 1], z = (*v)[i + 2];
                for (int r = 0; r < 3; ++r) (*v)[i + r] = float(R[3 * r] * x + R[3 * r + 1] * y + R[3 * r + 2] * z);
            }
    updateBounds(model);
}

}  // namespace

void placeModel(LoadedModel& model, const float half[3], const ModelPlacement& p) {
    if (p.up == 'z') {  // z-up to y-up: a turn of -90 degrees about x, (x, y, z) -> (x, z, -y)
        const double R[9] = {1, 0, 0, 0, 0, 1, 0, -1, 0};
        rotate(model, R);
    }
    if (p.yawDegrees != 0) {
        const double a = p.yawDegrees * 3.14159265358979323846 / 180, c = std::cos(a), s = std::sin(a);
        const double R[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
        rotate(model, R);
    }
    fitModel(model, half);
    // Seated on the chassis: a model whose height does not limit the fit (a long, low one) would
    // float in the middle of the box; it goes down onto the box's underside, where a model that
    // fills the box's height already is (ours: untouched, to the bit).
    const float drop = model.boundsMin[1] + half[1];
    if (drop > 1e-5f * half[1]) {
        for (MeshData& part : model.parts)
            for (std::size_t i = 1; i < part.positions.size(); i += 3) part.positions[i] -= drop;
        updateBounds(model);
    }
    if (p.scale == 1 && p.offset == std::array<double, 3>{0, 0, 0}) return;
    for (MeshData& part : model.parts)
        for (std::size_t i = 0; i < part.positions.size(); ++i)
            part.positions[i] = float(part.positions[i] * p.scale + p.offset[i % 3]);
    updateBounds(model);
}

}  // namespace engine
