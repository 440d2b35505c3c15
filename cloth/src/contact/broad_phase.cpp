#include "contact/broad_phase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

namespace cloth::contact {

namespace {

// A node (or two adjacent ones) whose normals lie within acos(kFlat) of one axis at every moment of
// the step cannot fold onto itself: 85 degrees, a margin under Volino's 90 for rounding.
constexpr Scalar kFlat = 0.087;
// A bound on a merged cone's rounding above the narrower of its two cones' cosines (about 1e-16).
constexpr Scalar kConeRounding = 1e-9;

// The box holding two boxes: the same bits as adding both to an empty box.
CLOTH_INLINE inline Box joined(const Box& a, const Box& b) {
    Box j;
    j.lo = a.lo.cwiseMin(b.lo), j.hi = a.hi.cwiseMax(b.hi);
    return j;
}

}  // namespace

void BroadPhase::prepare(const Model& model) {
    nx_ = model.gridNx(), ny_ = model.gridNy();
    if (nx_ < 2 || ny_ < 2) throw std::invalid_argument("contact: the cloth must be a grid");
    model_ = model.id();
    triangles_ = model.triangles();
    const int cells = (nx_ - 1) * (ny_ - 1);
    cellTriangles_.assign(cells, {}), cellVertices_.assign(cells, {}), cellEdges_.assign(cells, {});
    auto cellOf = [&](Index i, Index j) {
        const int r = std::min(std::min(i / nx_, j / nx_), ny_ - 2), c = std::min(std::min(i % nx_, j % nx_), nx_ - 2);
        return r * (nx_ - 1) + c;
    };
    std::map<std::pair<Index, Index>, Index> seen;
    edges_.clear();
    for (Index t = 0; t < Index(triangles_.size()); ++t) {
        const Triangle& tri = triangles_[t];
        const int r = std::min({tri[0] / nx_, tri[1] / nx_, tri[2] / nx_}), c = std::min({tri[0] % nx_, tri[1] % nx_, tri[2] % nx_});
        cellTriangles_[std::min(r, ny_ - 2) * (nx_ - 1) + std::min(c, nx_ - 2)].push_back(t);
        for (int k = 0; k < 3; ++k) {
            const Index i = std::min(tri[k], tri[(k + 1) % 3]), j = std::max(tri[k], tri[(k + 1) % 3]);
            if (seen.emplace(std::pair{i, j}, Index(edges_.size())).second) {
                cellEdges_[cellOf(i, j)].push_back(Index(edges_.size()));
                edges_.push_back({i, j});
            }
        }
    }
    cellCorners_.assign(cells, {});
    for (int c = 0; c < cells; ++c) {
        std::vector<Index> corners;
        for (Index t : cellTriangles_[c]) corners.insert(corners.end(), triangles_[t].begin(), triangles_[t].end());
        std::sort(corners.begin(), corners.end());
        corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
        if (corners.empty() || corners.size() > 4)
            throw std::invalid_argument("contact: a grid cell's triangles must have one to four corners");
        corners.resize(4, corners.back());  // a repeated corner changes no box
        std::copy(corners.begin(), corners.end(), cellCorners_[c].begin());
    }
    cellStamp_.assign(cells, 0), stamp_ = 0;
    edgeBox_.resize(edges_.size()), triangleBox_.resize(triangles_.size());
    row_.resize(model.particleCount()), col_.resize(model.particleCount());
    for (Index v = 0; v < model.particleCount(); ++v) {
        cellVertices_[cellOf(v, v)].push_back(v);
        row_[v] = v / nx_, col_[v] = v % nx_;
    }
    twoApartPairs();
    nodes_.clear();
    build(0, nx_ - 1, 0, ny_ - 1);
    leafCorners_.clear(), leaves_.clear(), leafStart_.assign(1, 0);
    for (int n = 0; n < int(nodes_.size()); ++n) {
        if (!nodes_[n].leaf()) continue;
        eachTriangle(nodes_[n], [&](Index t) { leafCorners_.add(triangles_[t]); });
        leaves_.push_back(n), leafStart_.push_back(leafCorners_.size());
    }
    leafAxis_.assign(leaves_.size(), Vec3::UnitZ());
    nearLeaves();
}

int BroadPhase::build(int c0, int c1, int r0, int r1) {
    const int n = int(nodes_.size());
    Node node;
    node.c0 = c0, node.c1 = c1, node.r0 = r0, node.r1 = r1;
    nodes_.push_back(node);
    if (c1 - c0 <= 2 && r1 - r0 <= 2) return n;
    const int cm = c1 - c0 > 2 ? (c0 + c1) / 2 : c1, rm = r1 - r0 > 2 ? (r0 + r1) / 2 : r1;
    int k = 0;
    for (auto [a, b] : {std::pair{c0, cm}, std::pair{cm, c1}})
        for (auto [p, q] : {std::pair{r0, rm}, std::pair{rm, r1}})
            if (a < b && p < q) {
                const int child = build(a, b, p, q);
                nodes_[n].child[k++] = child;
            }
    return n;
}

void BroadPhase::refit(const Model& model, const Points& y0, const Points& y1, Scalar margin) {
    if (model.id() != model_) prepare(model);
    const Index n = model.particleCount();
    vertexBox_.resize(n);
    for (Index i = 0; i < n; ++i) {
        const Vec3 a = y0.col(i), b = y1.col(i);
        Box& box = vertexBox_[i];
        box.lo = a.cwiseMin(b).array() - margin / 2, box.hi = a.cwiseMax(b).array() + margin / 2;
    }
    // A cell's box holds its triangles' corners; its edges' and triangles' own boxes are made
    // when a search first reaches the cell (fresh).
    cellBox_.resize(cellCorners_.size());
    for (std::size_t c = 0; c < cellCorners_.size(); ++c) {
        const auto& k = cellCorners_[c];
        cellBox_[c] = joined(joined(vertexBox_[k[0]], vertexBox_[k[1]]), joined(vertexBox_[k[2]], vertexBox_[k[3]]));
    }
    ++stamp_;
    margin_ = margin;
    refitBoxes();
    searched_.clear(), keptPairs_.clear();
}

void BroadPhase::widen(const Points& y0, const Points& y1, const std::vector<Scalar>& moves,
                       const std::vector<std::uint8_t>& pushed) {
    const std::size_t n = moves.size();
    reach_.resize(n);
    for (std::size_t i = 0; i < n; ++i) reach_[i] = 0.5 * moves[i] + (pushed.empty() || !pushed[i] ? 0 : margin_ / 2);
    motionCones(y0, y1, reach_, leafCorners_, coneScratch_, cones_);
    leafCones();
    refitCones(0);
}

// A node's triangles, leaf by leaf.
template <class F>
void BroadPhase::eachTriangle(const Node& node, F fn) const {
    for (int r = node.r0; r < node.r1; ++r)
        for (int c = node.c0; c < node.c1; ++c)
            for (Index t : cellTriangles_[r * (nx_ - 1) + c]) fn(t);
}

// Every node's box, children before parents (a child's index is above its parent's, build).
void BroadPhase::refitBoxes() {
    for (std::size_t n = nodes_.size(); n-- > 0;) {
        Node& node = nodes_[n];
        node.box = Box{};
        if (node.leaf()) {
            for (int r = node.r0; r < node.r1; ++r)
                for (int c = node.c0; c < node.c1; ++c) node.box.add(cellBox_[r * (nx_ - 1) + c]);
            continue;
        }
        for (int c : node.child)
            if (c >= 0) node.box.add(nodes_[std::size_t(c)].box);
    }
}

// Each leaf's cone: its axis the normalized sum of its triangles' axes, its angle their widest
// to it.
void BroadPhase::leafCones() {
    for (std::size_t j = 0; j < leaves_.size(); ++j) {
        Vec3 sum = Vec3::Zero();
        for (std::size_t k = leafStart_[j]; k < leafStart_[j + 1]; ++k) sum += cones_.axis(k);
        nodes_[std::size_t(leaves_[j])].axis = leafAxis_[j] = sum.norm() > 1e-12 ? Vec3(sum.normalized()) : Vec3::UnitZ();
    }
    widestToAxes(cones_, leafStart_, leafAxis_, coneScratch_, widest_);
    for (std::size_t j = 0; j < leaves_.size(); ++j) {
        Scalar cosHalf = 1;
        for (std::size_t k = leafStart_[j]; k < leafStart_[j + 1]; ++k) cosHalf = std::min(cosHalf, widest_[k]);
        Node& leaf = nodes_[std::size_t(leaves_[j])];
        leaf.cosHalf = cosHalf, leaf.partner = partnerCos(cosHalf, kFlat);
    }
}

// The nodes' cones above the leaves (leafCones).
void BroadPhase::refitCones(int n) {
    Node& node = nodes_[n];
    if (node.leaf()) return;
    bool first = true;
    for (int c : node.child) {
        if (c < 0) continue;
        refitCones(c);
        const Node& child = nodes_[c];
        if (first) nodes_[n].axis = child.axis, nodes_[n].cosHalf = child.cosHalf;
        else mergeCones(nodes_[n].axis, nodes_[n].cosHalf, child.axis, child.cosHalf, nodes_[n].axis, nodes_[n].cosHalf);
        first = false;
    }
    nodes_[n].partner = partnerCos(nodes_[n].cosHalf, kFlat);
}

// The boxes of a leaf's edges and triangles in this refit.
void BroadPhase::fresh(const Node& leaf) {
    for (int r = leaf.r0; r < leaf.r1; ++r)
        for (int c = leaf.c0; c < leaf.c1; ++c) {
            const int cell = r * (nx_ - 1) + c;
            if (cellStamp_[cell] == stamp_) continue;
            cellStamp_[cell] = stamp_;
            for (Index e : cellEdges_[cell]) edgeBox_[e] = joined(vertexBox_[edges_[e][0]], vertexBox_[edges_[e][1]]);
            for (Index t : cellTriangles_[cell]) {
                const Triangle& tri = triangles_[t];
                triangleBox_[t] = joined(joined(vertexBox_[tri[0]], vertexBox_[tri[1]]), vertexBox_[tri[2]]);
            }
        }
}

bool BroadPhase::far(Index u, Index v) const {
    return std::abs(row_[u] - row_[v]) > kExcludedCells || std::abs(col_[u] - col_[v]) > kExcludedCells;
}

bool BroadPhase::farTriangle(Index v, Index t) const {
    const Triangle& tri = triangles_[t];
    return far(v, tri[0]) && far(v, tri[1]) && far(v, tri[2]);
}

bool BroadPhase::farEdges(Index e, Index f) const {
    const auto &a = edges_[e], &b = edges_[f];
    return far(a[0], b[0]) && far(a[0], b[1]) && far(a[1], b[0]) && far(a[1], b[1]);
}

std::size_t BroadPhase::selfPairs(std::vector<Pair>& out, std::size_t most, const Keep& keep) {
    out.clear();
    Search search{out, most, keep};
    if (!nodes_.empty()) self(0, search);
    return search.found;
}

void BroadPhase::self(int n, Search& search) {
    const Node& node = nodes_[n];
    if (node.cosHalf > kFlat || node.leaf()) return;  // flat; a leaf's pairs are all within the springs' reach
    for (int i = 0; i < 4 && node.child[i] >= 0; ++i) {
        self(node.child[i], search);
        for (int j = i + 1; j < 4 && node.child[j] >= 0; ++j) cross(node.child[i], node.child[j], search);
    }
}

void BroadPhase::cross(int a, int b, Search& search) {
    const Node &A = nodes_[a], &B = nodes_[b];
    if (search.found > search.most || !A.box.overlaps(B.box)) return;
    const int span = std::max(std::max(A.c1, B.c1) - std::min(A.c0, B.c0), std::max(A.r1, B.r1) - std::min(A.r0, B.r0));
    if (span <= kExcludedCells) return;  // every pair within the springs' reach
    const bool adjacent = A.c0 <= B.c1 && B.c0 <= A.c1 && A.r0 <= B.r1 && B.r0 <= A.r1;
    // Two adjacent nodes whose joint cone is flat are one flat patch. The joint cone is no
    // narrower than either node's (up to rounding, far under kConeRounding): when one is not
    // flat, neither is it, and it is not computed.
    if (adjacent && std::min(A.cosHalf, B.cosHalf) > kFlat - kConeRounding &&
        mergedWithin(A.axis, A.cosHalf, A.partner, B.axis, B.cosHalf, B.partner, kFlat))
        return;
    if (A.leaf() && B.leaf()) return leaves(a, b, search);
    const bool splitA = !A.leaf() && (B.leaf() || (A.c1 - A.c0) * (A.r1 - A.r0) >= (B.c1 - B.c0) * (B.r1 - B.r0));
    const Node& big = splitA ? A : B;
    for (int c : big.child)
        if (c >= 0) cross(splitA ? c : a, splitA ? b : c, search);
}

// Two leaves' kept pairs: searched and kept at their first meeting since the refit (the boxes
// and so the candidates are the same until the next), reused after. Leaves none of whose cells
// meet have none, which is found again faster than it is looked up.
void BroadPhase::leaves(int a, int b, Search& search) {
    Meet meet;
    if (!cellsMeet(a, b, meet)) return;
    const auto [at, first] = searched_.try_emplace((std::uint64_t(a) << 32) | std::uint32_t(b));
    Searched& s = at->second;
    if (first) {
        candidates_.clear();
        fresh(nodes_[a]), fresh(nodes_[b]);
        leafPairs(nodes_[a], nodes_[b], meet, candidates_);
        s.begin = keptPairs_.size(), s.found = candidates_.size();
        for (Pair& p : candidates_)
            if (search.keep(p)) keptPairs_.push_back(p);
        s.end = keptPairs_.size();
    }
    search.found += s.found;
    search.out.insert(search.out.end(), keptPairs_.begin() + std::ptrdiff_t(s.begin), keptPairs_.begin() + std::ptrdiff_t(s.end));
}

// The candidates of two leaves whose cells meet (cellsMeet), after fresh.
void BroadPhase::leafPairs(const Node& A, const Node& B, const Meet& meet, std::vector<Pair>& out) const {
    // A primitive whose box misses the other node's box meets none of its primitives (their boxes
    // lie in it): flagged once per node pair and skipped, which keeps the pairs and their order.
    using Flags = std::array<std::array<bool, 8>, 4>;  // a leaf: at most 2 x 2 cells
    auto flag = [&](const Node& n, const std::vector<std::vector<Index>>& lists, const std::vector<Box>& boxes,
                    const Box& other) {
        Flags f{};
        eachCell(n, [&](const Cell& cell) {
            const auto& list = lists[cell.index];
            for (std::size_t i = 0; i < list.size() && i < 8; ++i) f[cell.k][i] = boxes[list[i]].overlaps(other);
        });
        return f;
    };
    auto vertexTriangles = [&](const Node& V, const Node& T, bool swapped) {
        const Flags in = flag(V, cellVertices_, vertexBox_, T.box);
        eachCell(V, [&](const Cell& cv) {
            eachCell(T, [&](const Cell& ct) {
                if (!(swapped ? meet[ct.k][cv.k] : meet[cv.k][ct.k])) return;
                const auto& vertices = cellVertices_[cv.index];
                for (std::size_t i = 0; i < vertices.size(); ++i) {
                    const Index v = vertices[i];
                    if (i < 8 && !in[cv.k][i]) continue;
                    for (Index t : cellTriangles_[ct.index])
                        if (vertexBox_[v].overlaps(triangleBox_[t]) && farTriangle(v, t))
                            out.push_back({Pair::Kind::VertexTriangle, v, t});
                }
            });
        });
    };
    vertexTriangles(A, B, false), vertexTriangles(B, A, true);
    const Flags inB = flag(A, cellEdges_, edgeBox_, B.box);
    eachCell(A, [&](const Cell& ca) {
        eachCell(B, [&](const Cell& cb) {
            if (!meet[ca.k][cb.k]) return;
            const auto& edges = cellEdges_[ca.index];
            for (std::size_t i = 0; i < edges.size(); ++i) {
                const Index e = edges[i];
                if (i < 8 && !inB[ca.k][i]) continue;
                for (Index f : cellEdges_[cb.index])
                    if (edgeBox_[e].overlaps(edgeBox_[f]) && farEdges(e, f)) out.push_back({Pair::Kind::EdgeEdge, e, f});
            }
        });
    });
}

void BroadPhase::near(const Box& box, const std::vector<std::uint8_t>& pinned, std::vector<Index>& vertices,
                      std::vector<Index>& edges) {
    vertices.clear(), edges.clear();
    std::vector<int> stack = {0};
    while (!stack.empty()) {
        const Node& n = nodes_[stack.back()];
        stack.pop_back();
        if (nodes_.empty() || !n.box.overlaps(box)) continue;
        if (!n.leaf()) {
            for (int c : n.child)
                if (c >= 0) stack.push_back(c);
            continue;
        }
        fresh(n);
        for (int r = n.r0; r < n.r1; ++r)
            for (int c = n.c0; c < n.c1; ++c) {
                const int cell = r * (nx_ - 1) + c;
                for (Index v : cellVertices_[cell])
                    if (!pinned[v] && vertexBox_[v].overlaps(box)) vertices.push_back(v);
                for (Index e : cellEdges_[cell])
                    if (edgeBox_[e].overlaps(box)) edges.push_back(e);
            }
    }
    std::sort(vertices.begin(), vertices.end()), std::sort(edges.begin(), edges.end());
}

}  // namespace cloth::contact
