#include "crossings/self.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "crossings/orient.h"

namespace cloth::crossings {

namespace {

constexpr int kMaxCell = (1 << 20) - 1;    // cell coordinates are clamped to [0, kMaxCell]
constexpr long kMaxCellsPerElement = 64;  // a larger box is kept out of the grid

struct Bounds { Vec3 lo, hi; };

// Closed boxes overlap: lo_a <= hi_b and lo_b <= hi_a on every axis.
bool overlap(const Bounds& a, const Bounds& b) {
    return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

struct CellRange {
    std::array<int, 3> lo{}, hi{};
    long cells() const { return long(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1); }
};

std::uint64_t cellKey(int ix, int iy, int iz) {
    return std::uint64_t(ix) | std::uint64_t(iy) << 20 | std::uint64_t(iz) << 40;
}

template <class F> void forEachCell(const CellRange& r, F&& f) {
    for (int iz = r.lo[2]; iz <= r.hi[2]; ++iz)
        for (int iy = r.lo[1]; iy <= r.hi[1]; ++iy)
            for (int ix = r.lo[0]; ix <= r.hi[0]; ++ix) f(ix, iy, iz);
}

// One or two triangles, first .. first + count - 1, and their box and cells; `listed` when
// finite and in the grid.
struct Unit {
    CellRange cells;
    Apartness::Span span{};  // grid models
    Index first = 0;
    int count = 1;
    bool finite = false, listed = false;
    Bounds box;
};

// The cells of a box: cell(v) = clamp(floor((v - origin) / side), 0, kMaxCell) on each axis, the
// clamp first so that truncation is floor (monotone in v, so the first cell two boxes share is
// the larger of their first cells).
class CellGrid {
public:
    CellGrid(const Vec3& origin, Scalar side) : origin_(origin), inverse_(1 / side) {}
    CellRange rangeOf(const Bounds& b) const {
        CellRange r;
        for (int a = 0; a < 3; ++a) {
            r.lo[a] = cell(b.lo(a), a);
            r.hi[a] = cell(b.hi(a), a);
        }
        return r;
    }

private:
    int cell(Scalar v, int axis) const {
        return int(std::clamp((v - origin_(axis)) * inverse_, Scalar(0), Scalar(kMaxCell)));
    }
    Vec3 origin_;
    Scalar inverse_;
};

// The listed units by cell: a cell's entries are in bucket hash(key), in unit order.
class CellTable {
public:
    void build(const std::vector<Unit>& units);
    // f(b) for the units b < a listed in the cell.
    template <class F> void forEachBefore(Index a, std::uint64_t key, F&& f) const {
        const std::size_t bucket = bucketOf(key);
        for (Index k = start_[bucket]; k < start_[bucket + 1] && units_[k] < a; ++k)
            if (keys_[k] == key) f(units_[k]);
    }

private:
    // Fibonacci hashing: the top bits of key * 2^64 / golden ratio.
    std::size_t bucketOf(std::uint64_t key) const { return std::size_t((key * 0x9E3779B97F4A7C15ull) >> shift_); }
    int shift_ = 63;
    std::vector<Index> start_, units_;
    std::vector<std::uint64_t> keys_;
};

// Counting sort of the (cell, unit) entries by bucket; at least as many buckets as entries.
void CellTable::build(const std::vector<Unit>& units) {
    long total = 0;
    for (const Unit& u : units)
        if (u.listed) total += u.cells.cells();
    int bits = 1;
    while ((1l << bits) < total) ++bits;
    shift_ = 64 - bits;
    start_.assign((std::size_t(1) << bits) + 1, 0);
    for (const Unit& u : units)
        if (u.listed) forEachCell(u.cells, [&](int ix, int iy, int iz) { ++start_[bucketOf(cellKey(ix, iy, iz)) + 1]; });
    for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    keys_.resize(std::size_t(total));
    units_.resize(std::size_t(total));
    std::vector<Index> fill(start_.begin(), start_.end() - 1);
    for (std::size_t a = 0; a < units.size(); ++a)
        if (units[a].listed)
            forEachCell(units[a].cells, [&](int ix, int iy, int iz) {
                const std::uint64_t key = cellKey(ix, iy, iz);
                const Index k = fill[bucketOf(key)]++;
                keys_[k] = key;
                units_[k] = Index(a);
            });
}

bool shareEdge(const Triangle& s, const Triangle& t) {
    int shared = 0;
    for (const Index v : s) shared += (v == t[0]) + (v == t[1]) + (v == t[2]);
    return shared == 2;
}

// One count of self crossings: the units' boxes and cells, the table, the pairs.
struct SelfPass {
    const Points& x;
    const MeshEdges& mesh;
    const std::vector<Triangle>& tris;
    Apartness apart;
    std::vector<Unit> units;
    CellTable table;
    int count = 0;

    SelfPass(const Model& model, const Points& positions, const MeshEdges& m)
        : x(positions), mesh(m), tris(model.triangles()), apart(model, m.edges) {}
    Unit unit(Index t, int count, bool allFinite) const;
    void bound();
    Scalar meanEdgeLength() const;
    void place(Scalar side);
    bool allNear(const Unit& a, const Unit& b) const {
        return apart.grid() ? Apartness::spansNear(a.span, b.span) : apart.cornersShared(a.first, a.count, b.first, b.count);
    }
    void judgeEdge(Index k, Index t);
    void judge(Index a, Index b);
    void gridPairs();
    void oversizePairs();
    void orphanPairs();
};

// Triangles t .. t + count - 1 as a unit, with its box and rows and columns.
Unit SelfPass::unit(Index t, int count, bool allFinite) const {
    Unit u;
    u.first = t;
    u.count = count;
    u.box.lo = u.box.hi = x.col(tris[t][0]);
    u.finite = true;
    for (Index s = t; s < t + count; ++s)
        for (const Index v : tris[s]) {
            u.box.lo = u.box.lo.cwiseMin(x.col(v));
            u.box.hi = u.box.hi.cwiseMax(x.col(v));
            u.finite = u.finite && (allFinite || x.col(v).allFinite());
        }
    if (apart.grid()) u.span = apart.span(t, count);
    return u;
}

// The units: a pair of triangles 2k, 2k + 1 sharing an edge unless one is not finite (a finite
// triangle must stay in the grid), else single triangles.
void SelfPass::bound() {
    const bool allFinite = x.allFinite();
    units.reserve(tris.size());
    for (Index t = 0; t < Index(tris.size()); t += units.back().count) {
        const bool pair = t % 2 == 0 && t + 1 < Index(tris.size()) && shareEdge(tris[t], tris[t + 1]);
        units.push_back(unit(t, pair ? 2 : 1, allFinite));
        if (pair && !units.back().finite) units.back() = unit(t, 1, allFinite);
    }
}

// The mean length of the edges with finite ends (0 when there are none); the sum skips the
// check of every end unless it comes out non-finite.
Scalar SelfPass::meanEdgeLength() const {
    Scalar sum = 0;
    for (const Edge& e : mesh.edges) sum += (x.col(e.q) - x.col(e.p)).norm();
    if (std::isfinite(sum)) return mesh.edges.empty() ? 0 : sum / Scalar(mesh.edges.size());
    sum = 0;
    long n = 0;
    for (const Edge& e : mesh.edges)
        if (x.col(e.p).allFinite() && x.col(e.q).allFinite()) {
            sum += (x.col(e.q) - x.col(e.p)).norm();
            ++n;
        }
    return n > 0 ? sum / Scalar(n) : 0;
}

// Cells of every finite unit, the grid's origin the low corner of them all.
void SelfPass::place(Scalar side) {
    Vec3 origin = Vec3::Constant(std::numeric_limits<Scalar>::max());
    for (const Unit& u : units)
        if (u.finite) origin = origin.cwiseMin(u.box.lo);
    const CellGrid grid(origin, side);
    for (Unit& u : units)
        if (u.finite) {
            u.cells = grid.rangeOf(u.box);
            u.listed = u.cells.cells() <= kMaxCellsPerElement;
        }
    table.build(units);
}

// Edge k against triangle t: boxes overlap, far apart, properly cross.
void SelfPass::judgeEdge(Index k, Index t) {
    const Edge& e = mesh.edges[k];
    const Triangle& tri = tris[t];
    const Vec3 p = x.col(e.p), q = x.col(e.q), a = x.col(tri[0]), b = x.col(tri[1]), c = x.col(tri[2]);
    const Bounds edgeBox{p.cwiseMin(q), p.cwiseMax(q)}, triBox{a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
    if (overlap(edgeBox, triBox) && apart.farApart(e, tri)) count += properlyCrosses(p, q, a, b, c);
}

// Two finite units: the edges of each against the triangles of the other, unless all near each
// other or apart in space.
void SelfPass::judge(Index a, Index b) {
    const Unit& ua = units[a];
    const Unit& ub = units[b];
    if (allNear(ua, ub) || !overlap(ua.box, ub.box)) return;
    for (const auto& [u, v] : {std::pair{&ua, &ub}, std::pair{&ub, &ua}})
        for (Index k = mesh.start[u->first]; k < mesh.start[u->first + u->count]; ++k)
            for (Index t = v->first; t < v->first + v->count; ++t) judgeEdge(k, t);
}

// Each listed unit against the listed units before it, in the first cell both boxes share.
void SelfPass::gridPairs() {
    for (Index a = 0; a < Index(units.size()); ++a) {
        if (!units[a].listed) continue;
        const CellRange& ra = units[a].cells;
        forEachCell(ra, [&](int ix, int iy, int iz) {
            table.forEachBefore(a, cellKey(ix, iy, iz), [&](Index b) {
                const CellRange& rb = units[b].cells;
                if (ix == std::max(ra.lo[0], rb.lo[0]) && iy == std::max(ra.lo[1], rb.lo[1]) &&
                    iz == std::max(ra.lo[2], rb.lo[2]))
                    judge(a, b);
            });
        });
    }
}

// Each finite unit out of the grid against every other finite one (two such, once).
void SelfPass::oversizePairs() {
    for (Index a = 0; a < Index(units.size()); ++a)
        if (units[a].finite && !units[a].listed)
            for (Index b = 0; b < Index(units.size()); ++b)
                if (units[b].finite && b != a && (units[b].listed || b > a)) judge(a, b);
}

// The edges with finite ends listed under a non-finite unit (met by no pair above) against
// every triangle of every finite unit.
void SelfPass::orphanPairs() {
    for (const Unit& ua : units) {
        if (ua.finite) continue;
        for (Index k = mesh.start[ua.first]; k < mesh.start[ua.first + ua.count]; ++k) {
            const Edge& e = mesh.edges[k];
            if (!x.col(e.p).allFinite() || !x.col(e.q).allFinite()) continue;
            for (const Unit& ub : units)
                if (ub.finite)
                    for (Index t = ub.first; t < ub.first + ub.count; ++t) judgeEdge(k, t);
        }
    }
}

}  // namespace

bool properlyCrosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    const int sp = orient3dSign(a, b, c, p);
    if (sp == 0 || orient3dSign(a, b, c, q) != -sp) return false;
    const int s = orient3dSign(p, q, a, b);
    return s != 0 && orient3dSign(p, q, b, c) == s && orient3dSign(p, q, c, a) == s;
}

int countSelfCrossings(const Model& model, const Points& x, const MeshEdges& mesh) {
    SelfPass pass(model, x, mesh);
    pass.bound();
    Scalar side = pass.meanEdgeLength();
    // Every finite edge has zero length: none can cross anything.
    if (!(side > 0)) return 0;
    // Lengths beyond the double range: one cell for everything (correct, only slower).
    if (!std::isfinite(side)) side = std::numeric_limits<Scalar>::max();
    pass.place(side);
    pass.gridPairs();
    pass.oversizePairs();
    pass.orphanPairs();
    return pass.count;
}

}  // namespace cloth::crossings
