#pragma once
// Immutable cloth topology and settings: masses, springs, triangles, rest shape, adjacency.
// Built once (from a grid or from an indexed triangle mesh), shared by any number of states.

#include <cstdint>
#include <array>
#include <string>
#include <vector>

#include "cloth/types.h"

namespace cloth {

enum class SpringKind : std::uint8_t { Structural = 0, Shear = 1, Bend = 2 };
const char* toString(SpringKind kind);

// Below this length a spring has no defined direction: force and Jacobian are zero.
constexpr Scalar kMinSpringLength = 1e-12;

struct Spring {
    Index i = 0, j = 0;
    SpringKind kind = SpringKind::Structural;
    Scalar k = 0;     // stiffness, N/m
    Scalar rest = 0;  // rest length, m
};

// A spring as the stretch limit reads it: its ends and rest length, half the bytes of a
// Spring, since the pass streams every spring several times per step.
struct PassSpring {
    Index i = 0, j = 0;
    Scalar rest = 0;  // m
};

using Triangle = std::array<Index, 3>;

// Stiffness per spring kind, N/m.
struct Stiffness {
    Scalar structural = 1e4;
    Scalar shear = 1e4;
    Scalar bend = 1e3;
    Scalar of(SpringKind kind) const;
};

// A rectangular grid of nx x ny particles. Particle (column c, row r) has index r * nx + c and
// rest position origin + c / (nx - 1) * width * axisU + r / (ny - 1) * height * axisV.
// Springs: structural (grid edges), shear (both quad diagonals), bend (skip-one along rows and
// columns), as in the paper. Mass is lumped from triangle areas (a third of each triangle's mass
// to each of its corners).
struct GridDesc {
    int nx = 33, ny = 33;
    Scalar width = 1.5, height = 1.0;
    Scalar totalMass = 0.3;  // kg
    Stiffness stiffness;
    Vec3 origin = Vec3::Zero();
    Vec3 axisU = Vec3::UnitX();
    Vec3 axisV = -Vec3::UnitY();
};

class Model {
public:
    // Throws std::invalid_argument with a message naming the field and value on bad input.
    static Model fromGrid(const GridDesc& desc);
    // Edges become structural springs; across each interior edge the two far vertices get a bend
    // spring with stiffness.bend. Shear stiffness is unused. Throws std::invalid_argument on
    // out-of-range indices, degenerate triangles or non-finite positions.
    static Model fromMesh(const Points& restPositions, const std::vector<Triangle>& triangles,
                          Scalar totalMass, const Stiffness& stiffness);

    int particleCount() const { return static_cast<int>(mass_.size()); }
    int springCount() const { return static_cast<int>(springs_.size()); }
    const std::vector<Scalar>& masses() const { return mass_; }
    const std::vector<Spring>& springs() const { return springs_; }
    const std::vector<Triangle>& triangles() const { return triangles_; }
    const Points& restPositions() const { return rest_; }
    // Grid size when built from a grid, {0, 0} otherwise.
    int gridNx() const { return nx_; }
    int gridNy() const { return ny_; }

    // Adjacency in compressed rows: the springs touching particle p are
    // adjSpring()[adjStart()[p] .. adjStart()[p + 1]), with the other end in adjOther().
    const std::vector<Index>& adjStart() const { return adjStart_; }
    const std::vector<Index>& adjSpring() const { return adjSpring_; }
    const std::vector<Index>& adjOther() const { return adjOther_; }
    // The triangles with corner p: triOf()[triStart()[p] .. triStart()[p + 1]), in increasing order.
    const std::vector<Index>& triStart() const { return triStart_; }
    const std::vector<Index>& triOf() const { return triOf_; }

    // The stretch limit's order (constraints.h), springs() in groups: group b < B
    // holds, in spring order, the springs with both ends in the b-th of B equal ranges of particle
    // indices (a band of rows on a grid); group B, the seam, every other spring, in spring order.
    // The first B groups share no particle, so they can run at once with the same bits; the seam
    // follows. B = particles / 4096, from 1 to 8: below 8,192 particles one group holds every
    // spring, in spring order. Group g is passSprings()[passGroupStart()[g] .. [g + 1]).
    int passBlocks() const { return static_cast<int>(passGroupStart_.size()) - 2; }
    const std::vector<Index>& passGroupStart() const { return passGroupStart_; }
    const std::vector<PassSpring>& passSprings() const { return passSprings_; }

    Scalar totalMass() const;
    // Identity for solver caches: every model built gets its own id; a copy shares it (a Model
    // never changes once built). Unlike an address, an id is never reused.
    std::uint64_t id() const { return id_; }

private:
    Model(Points rest, std::vector<Triangle> triangles, std::vector<Spring> springs, Scalar totalMass);
    void buildAdjacency();
    void groupSpringsForThePass();

    Points rest_;
    std::vector<Triangle> triangles_;
    std::vector<Spring> springs_;
    std::vector<Scalar> mass_;
    std::vector<Index> adjStart_, adjSpring_, adjOther_;
    std::vector<Index> triStart_, triOf_;
    std::vector<Index> passGroupStart_;
    std::vector<PassSpring> passSprings_;
    int nx_ = 0, ny_ = 0;
    std::uint64_t id_ = 0;
};

// Dynamic state, apart from the model: positions and velocities, one column per particle.
struct State {
    Points x;
    Points v;
    static State atRest(const Model& model);
};

}  // namespace cloth
