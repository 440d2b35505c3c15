#pragma once
// Models through assimp (glTF 2.0, OBJ, and whatever else it reads), validated: a model that is
// missing, unreadable, broken or hostile gives an error naming the file and the problem, never a
// crash. Degenerate triangles and non-triangle primitives are dropped (and counted).

#include <string>
#include <vector>

#include "engine/assets/model_placement.h"
#include "engine/mesh.h"

namespace engine {

struct ModelLimits {
    std::size_t maxVertices = 2'000'000;
    std::size_t maxTriangles = 2'000'000;
};

struct LoadedModel {
    std::vector<MeshData> parts;  // one per source mesh, node transforms applied, with base colour
    std::size_t droppedTriangles = 0;
    float boundsMin[3] = {0, 0, 0}, boundsMax[3] = {0, 0, 0};
};

// Throws ConfigError naming the file and what is wrong with it.
LoadedModel loadModel(const std::string& path, const ModelLimits& limits = {});

// Scales and moves the parts so that their bounding box fits `halfExtents` around the origin
// (uniform scale, centred), e.g. to fit any model onto the physics chassis.
void fitModel(LoadedModel& model, const float halfExtents[3]);

// The scene's placement: the model turned so that its up axis is +y and by its yaw, fitted onto
// `halfExtents` (fitModel) and seated on the box's underside (a model lower than the box no longer
// floats in its middle), then scaled about the centre and offset. For a model whose height fills
// the box, the default placement is fitModel alone, to the bit.
void placeModel(LoadedModel& model, const float halfExtents[3], const ModelPlacement& placement);

}  // namespace engine
