#pragma once
// The contact stage's broad phase on a grid cloth: which primitives may come within reach of each
// other, or of an obstacle, during one step. A quadtree over the grid's cells (built once per
// model) holds, after each refit, every node's box swept over the step (its particles at the start
// and at the end, grown by a margin) and its normal cone: every normal its triangles can take
// during the step, within a half-angle of an axis, while each particle keeps to its straight move
// or, where the contact stage may push it, within margin / 2 of that move (cones at the step's two
// ends alone miss a patch that folds on the way).
//   - Self pairs: vertex-triangle and edge-edge pairs at least kExcludedCells + 1 cells apart whose
//     swept boxes overlap. A node whose normals lie within 90 degrees of one axis cannot fold onto
//     itself (Volino and Magnenat-Thalmann 1994), nor can two adjacent nodes whose joint cone does:
//     such nodes are not searched.
//   - Obstacle primitives: free vertices and mesh edges whose swept boxes reach an obstacle's box.
// Each vertex and each mesh edge belongs to one cell, so that no pair is listed twice.

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "cloth/model.h"
#include "cloth/parallel_for.h"
#include "contact/cones.h"

namespace cloth::contact {

// Pairs of the grid within this many cells of each other are left to the cloth's springs.
constexpr int kExcludedCells = 2;
// A node (or two adjacent ones) whose normals lie within acos(kFlat) of one axis at every moment of
// the step cannot fold onto itself: 85 degrees, a margin under Volino's 90 for rounding.
constexpr Scalar kFlat = 0.087;
// A bound on a merged cone's rounding above the narrower of its two cones' cosines (about 1e-16).
constexpr Scalar kConeRounding = 1e-9;

struct Box {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    void add(const Vec3& p) { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); }
    void add(const Box& b) { lo = lo.cwiseMin(b.lo), hi = hi.cwiseMax(b.hi); }
    // All six comparisons made, without branches: about half the boxes the search tests meet,
    // which a branch mispredicts.
    bool overlaps(const Box& b) const {
        const int met = int(lo.x() <= b.hi.x()) & int(lo.y() <= b.hi.y()) & int(lo.z() <= b.hi.z()) &
                        int(b.lo.x() <= hi.x()) & int(b.lo.y() <= hi.y()) & int(b.lo.z() <= hi.z());
        return met != 0;
    }
};

struct Pair {
    enum class Kind : std::uint8_t { VertexTriangle, EdgeEdge } kind;
    Index a = 0, b = 0;  // vertex and triangle, or the two edges (indices into mesh edges)
    Scalar gap = 0;      // what the search's Keep records: the pair's distance at the step's start
};

// Whether a candidate self pair is kept (it may fill in the pair's gap). It must give the same
// answer for a pair until the next refit: the search keeps its answers.
using Keep = std::function<bool(Pair&)>;

class BroadPhase {
public:
    // The grid's quadtree, its mesh edges and each primitive's cell; redone when the model changes.
    void prepare(const Model& model);
    // The swept boxes of the step from y0 to y1 (carrier frame), grown by margin; each cell's edges'
    // and triangles' boxes are made when a search first reaches it.
    void refit(const Model& model, const Points& y0, const Points& y1, Scalar margin, ParallelFor* loops = nullptr);
    // The normal cones of the step's motion (after refit, before selfPairs): each particle on its
    // straight move (moves[i] its length, |y1_i - y0_i|), or anywhere within margin / 2 of it where
    // `pushed` flags it (the contact stage's pushes).
    void widen(const Points& y0, const Points& y1, const std::vector<Scalar>& moves, const std::vector<std::uint8_t>& pushed,
               ParallelFor* loops = nullptr);
    // The self pairs that may touch during the step and that `keep` keeps, in the order of the
    // tree's search. Returns the candidates found: past `most` the search stops. Within one refit,
    // each two leaves are searched and their candidates kept once: a later call (wider cones after
    // another widen, which open more nodes) reuses them, so it costs only the tree's walk. The
    // tree's walk lists the two leaves to search; `loops` searches them on its threads (`keep`
    // must allow that), the same pairs in the same order (broad_phase_search.cpp).
    std::size_t selfPairs(std::vector<Pair>& out, std::size_t most, const Keep& keep, ParallelFor* loops = nullptr);
    // The free vertices and mesh edges whose swept boxes reach `box`.
    void near(const Box& box, const std::vector<std::uint8_t>& pinned, std::vector<Index>& vertices,
              std::vector<Index>& edges);

    const std::vector<std::array<Index, 2>>& edges() const { return edges_; }
    std::uint64_t model() const { return model_; }

private:
    struct Node {
        int c0 = 0, c1 = 0, r0 = 0, r1 = 0;  // its cells: columns [c0, c1), rows [r0, r1)
        int child[4] = {-1, -1, -1, -1};
        Box box;
        Vec3 axis = Vec3::UnitZ();
        Scalar cosHalf = 1;  // every normal n has n . axis >= cosHalf (a cone of half-angle acos)
        Scalar partner = 2;  // partnerCos(cosHalf, kFlat): for a flat node, how far another's axis may turn
        bool leaf() const { return child[0] < 0; }
    };
    int build(int c0, int c1, int r0, int r1);
    template <class F>
    void eachTriangle(const Node& node, F fn) const;
    void refitBoxes();
    void fresh(const Node& leaf);
    void freshCell(int cell);
    void leafCones(ParallelFor* loops);
    void refitCones(int n);
    // Two leaves the tree's walk reaches, and what their search found: `found` candidates, and
    // the kept ones in [begin, end) of keptPairs_ (cached) or of their stripe's pairs.
    struct Visit {
        int a = 0, b = 0;
        std::size_t found = 0, begin = 0, end = 0;
        bool met = false, cached = false;
    };
    // A part of the walk (broad_phase_search.cpp): node a's own pairs (b < 0) or a's with b's; its
    // visits are [begin, end) of its stripe's.
    struct Task {
        int a = 0, b = -1;
        int stripe = 0;
        std::size_t begin = 0, end = 0;
    };
    struct alignas(64) Stripe {  // one thread's share of the tasks (a cache line of its own)
        std::vector<Visit> visits;
        std::vector<Pair> pairs, candidates;  // its kept pairs; one visit's candidates
        std::size_t found = 0, most = 0;
        const Keep* keep = nullptr;
    };
    int cellsOf(int n) const;
    bool skipSelf(int n) const;
    bool skipCross(int a, int b) const;
    bool splitsFirst(int a, int b) const;
    struct Planner;
    struct Walker;
    template <class To>
    void walkSelf(int n, To& to);
    template <class To>
    void walkCross(int a, int b, To& to);
    void plan();
    void runStripe(int s, int stripes, std::size_t most, const Keep& keep);
    void search(Visit& v, Stripe& stripe);
    std::size_t gatherTasks(std::vector<Pair>& out, std::size_t most);
    struct Cell {
        int index, k, r, c;  // the cell, its place in its leaf, its row and column
    };
    template <class F>
    void eachCell(const Node& n, F fn) const;
    using Meet = std::array<std::array<bool, 4>, 4>;  // two leaves' cells that may hold a pair
    bool cellsMeet(int a, int b, Meet& meet) const;
    bool apartPairs(int a, int dr, int dc) const;
    void twoApartPairs();
    void nearLeaves();
    std::uint16_t farCells(int a, int b) const;
    void leafPairs(const Node& a, const Node& b, const Meet& meet, std::vector<Pair>& out) const;
    bool far(Index u, Index v) const;  // more than kExcludedCells cells apart
    bool farTriangle(Index v, Index t) const;
    bool farEdges(Index e, Index f) const;

    std::uint64_t model_ = 0;
    int nx_ = 0, ny_ = 0;
    std::vector<int> row_, col_;  // each particle's place in the grid
    std::vector<Node> nodes_;
    std::vector<std::array<Index, 2>> edges_;
    std::vector<Triangle> triangles_;
    // Per cell: its triangles, the vertices and edges it owns.
    std::vector<std::vector<Index>> cellTriangles_, cellVertices_, cellEdges_;
    std::vector<Box> vertexBox_, edgeBox_, triangleBox_, cellBox_;
    std::vector<std::array<Index, 4>> cellCorners_;  // per cell: its triangles' corners (the last repeated up to four)
    std::vector<std::uint16_t> twoApart_;  // per cell: bit twoApartBit(dr, dc) if the cell there holds a far pair with it
    // Per node, for a leaf: its cells (in eachCell's order, the rest -1), and the leaves within two
    // cells of it, each with the bits 4 ka + kb of the two leaves' cells that hold a far pair
    // (apartPairs). Leaves further apart hold one in any two cells.
    std::vector<std::array<int, 4>> leafCells_;
    std::vector<std::vector<std::pair<int, std::uint16_t>>> nearLeaves_;
    std::vector<std::atomic<std::uint64_t>> cellStamp_;  // per cell: 2 x the refit its edges' and triangles' boxes are of (freshCell)
    std::uint64_t stamp_ = 0;                      // refits since prepare
    Scalar margin_ = 0;
    std::vector<Scalar> reach_;      // each particle's distance from its move's midpoint, at most
    Corners leafCorners_;            // the triangles leaf by leaf, each leaf's in eachTriangle's order
    Cones cones_;                    // each leafCorners_ triangle's normal cone over the step
    ConeScratch coneScratch_;
    std::vector<int> leaves_;        // the leaves, in node order
    std::vector<std::size_t> leafStart_;  // leaves_[j]'s triangles: [leafStart_[j], leafStart_[j + 1]) of leafCorners_
    std::vector<Vec3> leafAxis_;     // per leaves_ entry: its axis (the normalized sum of its triangles')
    std::vector<Scalar> widest_;     // per leafCorners_ triangle: the cosine of its cone's widest angle to its leaf's axis
    // Since the last refit: each two leaves searched (key a << 32 | b), their kept pairs in
    // keptPairs_ [begin, end) and their candidates' count.
    struct Searched {
        std::size_t begin = 0, end = 0, found = 0;
    };
    std::unordered_map<std::uint64_t, Searched> searched_;
    std::vector<Pair> keptPairs_;
    std::vector<Task> tasks_;      // this search's, in the walk's order
    int taskCells_ = 0;            // a task's nodes hold at most this many cells each
    std::vector<Stripe> stripes_;
};

// A leaf's cells in order: each with its index, its place in the leaf, its row and column.
template <class F>
void BroadPhase::eachCell(const Node& n, F fn) const {
    int k = 0;
    for (int r = n.r0; r < n.r1; ++r)
        for (int c = n.c0; c < n.c1; ++c) fn(Cell{r * (nx_ - 1) + c, k++, r, c});
}

}  // namespace cloth::contact
