#include "cloth/model.h"

#include <atomic>
#include <algorithm>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace cloth {

const char* toString(SpringKind kind) {
    switch (kind) {
        case SpringKind::Structural: return "structural";
        case SpringKind::Shear: return "shear";
        case SpringKind::Bend: return "bend";
    }
    return "?";
}

Scalar Stiffness::of(SpringKind kind) const {
    switch (kind) {
        case SpringKind::Structural: return structural;
        case SpringKind::Shear: return shear;
        case SpringKind::Bend: return bend;
    }
    return 0;
}

namespace {

template <class T>
[[noreturn]] void fail(const char* field, const T& value, const char* why) {
    std::ostringstream s;
    s << field << " = " << value << ": " << why;
    throw std::invalid_argument(s.str());
}

void checkPositive(const char* field, Scalar value) {
    if (!std::isfinite(value) || value <= 0) fail(field, value, "must be a positive finite number");
}

void checkStiffness(const Stiffness& k, bool needShear) {
    checkPositive("stiffness.structural", k.structural);
    if (needShear) checkPositive("stiffness.shear", k.shear);
    if (!std::isfinite(k.bend) || k.bend < 0) fail("stiffness.bend", k.bend, "must be finite and >= 0");
}

}  // namespace

// Largest grid side we accept: 2^20 particles is far beyond real time and keeps indices in int32.
constexpr int kMaxGridSide = 1024;

Model Model::fromGrid(const GridDesc& d) {
    if (d.nx < 2 || d.nx > kMaxGridSide) fail("nx", d.nx, "must be in [2, 1024]");
    if (d.ny < 2 || d.ny > kMaxGridSide) fail("ny", d.ny, "must be in [2, 1024]");
    checkPositive("width", d.width);
    checkPositive("height", d.height);
    checkPositive("totalMass", d.totalMass);
    checkStiffness(d.stiffness, true);
    if (!d.origin.allFinite() || !d.axisU.allFinite() || !d.axisV.allFinite())
        fail("origin/axis", "non-finite", "must be finite");
    if (d.axisU.norm() < 1e-9 || d.axisV.norm() < 1e-9 || d.axisU.cross(d.axisV).norm() < 1e-9)
        fail("axisU/axisV", "degenerate", "must be non-zero and not parallel");

    const int nx = d.nx, ny = d.ny;
    const Vec3 du = d.axisU.normalized() * (d.width / (nx - 1));
    const Vec3 dv = d.axisV.normalized() * (d.height / (ny - 1));
    Points rest(3, nx * ny);
    auto id = [nx](int c, int r) { return static_cast<Index>(r * nx + c); };
    for (int r = 0; r < ny; ++r)
        for (int c = 0; c < nx; ++c) rest.col(id(c, r)) = d.origin + c * du + r * dv;

    std::vector<Triangle> tris;
    tris.reserve(2 * (nx - 1) * (ny - 1));
    for (int r = 0; r + 1 < ny; ++r)
        for (int c = 0; c + 1 < nx; ++c) {
            // Alternate the diagonal so the mesh has no preferred direction.
            if ((r + c) % 2 == 0) {
                tris.push_back({id(c, r), id(c, r + 1), id(c + 1, r + 1)});
                tris.push_back({id(c, r), id(c + 1, r + 1), id(c + 1, r)});
            } else {
                tris.push_back({id(c, r), id(c, r + 1), id(c + 1, r)});
                tris.push_back({id(c + 1, r), id(c, r + 1), id(c + 1, r + 1)});
            }
        }

    std::vector<Spring> springs;
    auto add = [&](Index i, Index j, SpringKind kind) {
        springs.push_back({i, j, kind, d.stiffness.of(kind), (rest.col(j) - rest.col(i)).norm()});
    };
    for (int r = 0; r < ny; ++r)
        for (int c = 0; c < nx; ++c) {
            if (c + 1 < nx) add(id(c, r), id(c + 1, r), SpringKind::Structural);
            if (r + 1 < ny) add(id(c, r), id(c, r + 1), SpringKind::Structural);
        }
    for (int r = 0; r + 1 < ny; ++r)
        for (int c = 0; c + 1 < nx; ++c) {
            add(id(c, r), id(c + 1, r + 1), SpringKind::Shear);
            add(id(c + 1, r), id(c, r + 1), SpringKind::Shear);
        }
    if (d.stiffness.bend > 0)
        for (int r = 0; r < ny; ++r)
            for (int c = 0; c < nx; ++c) {
                if (c + 2 < nx) add(id(c, r), id(c + 2, r), SpringKind::Bend);
                if (r + 2 < ny) add(id(c, r), id(c, r + 2), SpringKind::Bend);
            }

    Model m(std::move(rest), std::move(tris), std::move(springs), d.totalMass);
    m.nx_ = nx;
    m.ny_ = ny;
    return m;
}

Model Model::fromMesh(const Points& rest, const std::vector<Triangle>& tris, Scalar totalMass,
                      const Stiffness& stiffness) {
    const Index n = static_cast<Index>(rest.cols());
    if (n < 3) fail("vertices", n, "a cloth mesh needs at least 3 vertices");
    if (tris.empty()) fail("triangles", 0, "a cloth mesh needs at least one triangle");
    if (!rest.allFinite()) fail("vertices", "non-finite", "positions must be finite");
    checkPositive("totalMass", totalMass);
    checkStiffness(stiffness, false);

    // Edge -> the far vertices of the triangles that share it.
    std::map<std::pair<Index, Index>, std::vector<Index>> edges;
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const Triangle& tri = tris[t];
        for (int e = 0; e < 3; ++e) {
            const Index a = tri[e];
            if (a < 0 || a >= n) fail("triangle index", a, "out of range");
        }
        const Vec3 ab = rest.col(tri[1]) - rest.col(tri[0]);
        const Vec3 ac = rest.col(tri[2]) - rest.col(tri[0]);
        if (ab.cross(ac).norm() < 1e-12) fail("triangle", t, "is degenerate (zero area)");
        for (int e = 0; e < 3; ++e) {
            const Index a = tri[e], b = tri[(e + 1) % 3], far = tri[(e + 2) % 3];
            edges[{std::min(a, b), std::max(a, b)}].push_back(far);
        }
    }
    std::vector<Spring> springs;
    for (const auto& [edge, fars] : edges) {
        const auto [a, b] = edge;
        springs.push_back({a, b, SpringKind::Structural, stiffness.structural,
                           (rest.col(b) - rest.col(a)).norm()});
    }
    if (stiffness.bend > 0)
        for (const auto& [edge, fars] : edges)
            if (fars.size() == 2 && fars[0] != fars[1]) {
                const Index a = std::min(fars[0], fars[1]), b = std::max(fars[0], fars[1]);
                springs.push_back({a, b, SpringKind::Bend, stiffness.bend,
                                   (rest.col(b) - rest.col(a)).norm()});
            }
    return Model(rest, tris, std::move(springs), totalMass);
}

Model::Model(Points rest, std::vector<Triangle> triangles, std::vector<Spring> springs,
             Scalar totalMass)
    : rest_(std::move(rest)), triangles_(std::move(triangles)), springs_(std::move(springs)) {
    static std::atomic<std::uint64_t> lastId{0};
    id_ = ++lastId;
    // Lumped mass: each triangle gives a third of its share of the total mass to each corner.
    const Index n = static_cast<Index>(rest_.cols());
    std::vector<Scalar> area(triangles_.size());
    Scalar totalArea = 0;
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
        const Triangle& tri = triangles_[t];
        area[t] = 0.5 * (rest_.col(tri[1]) - rest_.col(tri[0]))
                            .cross(rest_.col(tri[2]) - rest_.col(tri[0]))
                            .norm();
        totalArea += area[t];
    }
    mass_.assign(n, 0);
    for (std::size_t t = 0; t < triangles_.size(); ++t)
        for (Index v : triangles_[t]) mass_[v] += totalMass * area[t] / totalArea / 3;
    // A vertex in no triangle still needs a mass for W to stay invertible.
    const Scalar floorMass = totalMass / n * 1e-3;
    for (Scalar& m : mass_) m = std::max(m, floorMass);
    buildAdjacency();
    groupSpringsForThePass();
}

void Model::buildAdjacency() {
    const Index n = particleCount();
    adjStart_.assign(n + 1, 0);
    for (const Spring& s : springs_) {
        ++adjStart_[s.i + 1];
        ++adjStart_[s.j + 1];
    }
    for (Index p = 0; p < n; ++p) adjStart_[p + 1] += adjStart_[p];
    adjSpring_.resize(adjStart_[n]);
    adjOther_.resize(adjStart_[n]);
    std::vector<Index> fill(adjStart_.begin(), adjStart_.end() - 1);
    for (Index s = 0; s < springCount(); ++s) {
        const Spring& sp = springs_[s];
        adjSpring_[fill[sp.i]] = s;
        adjOther_[fill[sp.i]++] = sp.j;
        adjSpring_[fill[sp.j]] = s;
        adjOther_[fill[sp.j]++] = sp.i;
    }
    triStart_.assign(n + 1, 0);
    for (const Triangle& t : triangles_)
        for (const Index p : t) ++triStart_[p + 1];
    for (Index p = 0; p < n; ++p) triStart_[p + 1] += triStart_[p];
    triOf_.resize(triStart_[n]);
    fill.assign(triStart_.begin(), triStart_.end() - 1);
    for (std::size_t t = 0; t < triangles_.size(); ++t)
        for (const Index p : triangles_[t]) triOf_[fill[p]++] = Index(t);
}

void Model::groupSpringsForThePass() {
    const Index n = particleCount();
    const Index blocks = std::clamp<Index>(n / 4096, 1, 8);
    auto blockOf = [&](Index p) { return Index(std::int64_t(p) * blocks / n); };
    std::vector<Index> group(springs_.size());
    for (std::size_t s = 0; s < springs_.size(); ++s) {
        const Index a = blockOf(springs_[s].i), b = blockOf(springs_[s].j);
        group[s] = a == b ? a : blocks;
    }
    passGroupStart_.assign(blocks + 2, 0);
    for (const Index g : group) ++passGroupStart_[g + 1];
    for (Index g = 0; g <= blocks; ++g) passGroupStart_[g + 1] += passGroupStart_[g];
    passSprings_.resize(springs_.size());
    std::vector<Index> fill(passGroupStart_.begin(), passGroupStart_.end() - 1);
    for (std::size_t s = 0; s < springs_.size(); ++s)
        passSprings_[fill[group[s]]++] = {springs_[s].i, springs_[s].j, springs_[s].rest};
}

Scalar Model::totalMass() const {
    Scalar m = 0;
    for (Scalar mi : mass_) m += mi;
    return m;
}

State State::atRest(const Model& model) {
    State s;
    s.x = model.restPositions();
    s.v = Points::Zero(3, model.particleCount());
    return s;
}

}  // namespace cloth
