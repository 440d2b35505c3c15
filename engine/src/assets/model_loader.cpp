#include "engine/assets/model_loader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>

#include "engine/config_error.h"

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

}  // namespace engine
