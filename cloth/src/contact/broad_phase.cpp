#include "contact/broad_phase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

namespace cloth::contact {

namespace {

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
    cellStamp_ = std::vector<std::atomic<std::uint64_t>>(std::size_t(cells)), stamp_ = 0;
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

void BroadPhase::refit(const Model& model, const Points& y0, const Points& y1, Scalar margin, ParallelFor* loops) {
    if (model.id() != model_) prepare(model);
    const Index n = model.particleCount();
    vertexBox_.resize(n);
    forChunks(loops, int(n), [&](int begin, int end) {
        for (Index i = begin; i < end; ++i) {
            const Vec3 a = y0.col(i), b = y1.col(i);
            Box& box = vertexBox_[i];
            box.lo = a.cwiseMin(b).array() - margin / 2, box.hi = a.cwiseMax(b).array() + margin / 2;
        }
    });
    // A cell's box holds its triangles' corners; its edges' and triangles' own boxes are made
    // when a search first reaches the cell (fresh).
    cellBox_.resize(cellCorners_.size());
    forChunks(loops, int(cellCorners_.size()), [&](int begin, int end) {
        for (int c = begin; c < end; ++c) {
            const auto& k = cellCorners_[std::size_t(c)];
            cellBox_[std::size_t(c)] = joined(joined(vertexBox_[k[0]], vertexBox_[k[1]]), joined(vertexBox_[k[2]], vertexBox_[k[3]]));
        }
    });
    ++stamp_;
    margin_ = margin;
    refitBoxes();
    searched_.clear(), keptPairs_.clear();
}

void BroadPhase::widen(const Points& y0, const Points& y1, const std::vector<Scalar>& moves,
                       const std::vector<std::uint8_t>& pushed, ParallelFor* loops) {
    const std::size_t n = moves.size();
    reach_.resize(n);
    forChunks(loops, int(n), [&](int begin, int end) {
        for (int i = begin; i < end; ++i)
            reach_[std::size_t(i)] = 0.5 * moves[std::size_t(i)] + (pushed.empty() || !pushed[std::size_t(i)] ? 0 : margin_ / 2);
    });
    motionCones(y0, y1, reach_, leafCorners_, coneScratch_, cones_, loops);
    leafCones(loops);
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
void BroadPhase::leafCones(ParallelFor* loops) {
    forChunks(loops, int(leaves_.size()), [&](int begin, int end) {
        for (std::size_t j = std::size_t(begin); j < std::size_t(end); ++j) {
            Vec3 sum = Vec3::Zero();
            for (std::size_t k = leafStart_[j]; k < leafStart_[j + 1]; ++k) sum += cones_.axis(k);
            nodes_[std::size_t(leaves_[j])].axis = leafAxis_[j] = sum.norm() > 1e-12 ? Vec3(sum.normalized()) : Vec3::UnitZ();
        }
    });
    widestToAxes(cones_, leafStart_, leafAxis_, coneScratch_, widest_, loops);
    forChunks(loops, int(leaves_.size()), [&](int begin, int end) {
        for (std::size_t j = std::size_t(begin); j < std::size_t(end); ++j) {
            Scalar cosHalf = 1;
            for (std::size_t k = leafStart_[j]; k < leafStart_[j + 1]; ++k) cosHalf = std::min(cosHalf, widest_[k]);
            Node& leaf = nodes_[std::size_t(leaves_[j])];
            leaf.cosHalf = cosHalf, leaf.partner = partnerCos(cosHalf, kFlat);
        }
    });
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
        for (int c = leaf.c0; c < leaf.c1; ++c) freshCell(r * (nx_ - 1) + c);
}

// The boxes of a cell's edges and triangles in this refit, unless made (each cell owns its edges
// and triangles). Searches on several threads may reach a cell at once: the first to claim it
// (its stamp 2 refits - 1) makes them, the others wait until it is done (2 refits).
void BroadPhase::freshCell(int cell) {
    std::atomic<std::uint64_t>& stamp = cellStamp_[std::size_t(cell)];
    const std::uint64_t made = 2 * stamp_, making = made - 1;
    std::uint64_t seen = stamp.load(std::memory_order_acquire);
    if (seen == made) return;
    if (seen != making && stamp.compare_exchange_strong(seen, making, std::memory_order_acq_rel)) {
        for (Index e : cellEdges_[std::size_t(cell)]) edgeBox_[e] = joined(vertexBox_[edges_[e][0]], vertexBox_[edges_[e][1]]);
        for (Index t : cellTriangles_[std::size_t(cell)]) {
            const Triangle& tri = triangles_[t];
            triangleBox_[t] = joined(joined(vertexBox_[tri[0]], vertexBox_[tri[1]]), vertexBox_[tri[2]]);
        }
        stamp.store(made, std::memory_order_release);
        return;
    }
    while (stamp.load(std::memory_order_acquire) != made) {
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
