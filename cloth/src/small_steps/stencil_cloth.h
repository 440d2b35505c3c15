#pragma once
// A grid cloth in the stencil layout of the small_steps solver, in float: positions relative to an
// origin near the flag (the first pin), so float keeps its 24 bits for the cloth's own size
// wherever the carrier has driven; velocities in the world frame.
//  - every per-particle quantity is a structure-of-arrays vector indexed by p = row * nx + col,
//    padded on both sides by the largest spring offset, so no loop tests bounds;
//  - springs fall into families of constant offset d (kangcho/stencil.h's springFamilies): the
//    spring of family f at slot p joins p to p + d, a slot with no spring has k = 0;
//  - the air acts on the grid's triangles, two per quad with the diagonal alternating as
//    Model::fromGrid lays them: quad p has corners p, p + 1, p + nx, p + nx + 1, and its two
//    triangles are {p, p + nx, c1} and {a2, p + 1, p + nx + 1} with c1 = p + nx + 1, a2 = p on an
//    even quad ((row + col) even), c1 = p + 1, a2 = p + nx on an odd one.

#include <cstdint>
#include <string>
#include <vector>

#include "cloth/model.h"

namespace cloth {

// One padded float vector: element i at at()[i], i in [-pad, n + pad).
struct PaddedField {
    std::vector<float> storage;
    int pad = 0;
    void assign(int n, int padding) {
        pad = padding;
        storage.assign(std::size_t(n) + 2 * std::size_t(padding), 0.0f);
    }
    float* at() { return storage.data() + pad; }
    const float* at() const { return storage.data() + pad; }
};

struct Vec3Field {
    PaddedField x, y, z;
    void assign(int n, int padding) { x.assign(n, padding), y.assign(n, padding), z.assign(n, padding); }
};

// What does not change while the model stays the same: springs by family, masses, quads.
struct StencilCloth {
    int n = 0, nx = 0, ny = 0, pad = 0;
    std::uint64_t modelId = 0;
    std::vector<int> offsets;  // one per family, increasing
    std::vector<PaddedField> k, rest;
    PaddedField invMass;             // 1 / m (0 in the padding)
    PaddedField quadValid, quadEven; // 1 or 0 per quad slot p

    // Builds the layout of `model`; an empty string, or why the model has none (not a grid laid
    // out as Model::fromGrid lays it).
    std::string build(const Model& model);
};

// The per-step state: positions relative to `origin`, world velocities, and the scratch of the
// forces (per family, the spring force at its slot; per quad, the air's share at each corner).
struct StencilState {
    Vec3Field x, v;
    std::vector<Vec3Field> spring;  // per family
    Vec3Field corner[4];            // quad corners p, p + 1, p + nx, p + nx + 1
    PaddedField scratch;            // per particle (the colliders' reject)
    void assign(const StencilCloth& cloth);
};

}  // namespace cloth
