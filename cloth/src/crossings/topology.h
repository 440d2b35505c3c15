#pragma once
// The mesh as the crossing checker (cloth/crossings.h) reads it: its unique edges, and which
// (edge, triangle) pairs are far enough apart to be judged.

#include <array>
#include <vector>

#include "cloth/model.h"

namespace cloth::crossings {

struct Edge { Index p = 0, q = 0; };  // p < q

// The unique edges of model.triangles(), each listed under the first triangle that has it:
// those of triangle t are edges[start[t] .. start[t + 1]).
struct MeshEdges {
    std::vector<Edge> edges;
    std::vector<Index> start;
};
MeshEdges meshEdges(const Model& model);

// Whether an edge and a triangle are at least three cells apart: on a grid model, every pair
// (u of the edge, w of the triangle) has max(|row_u - row_w|, |col_u - col_w|) >= 3; otherwise
// no vertex of the triangle is within 2 mesh edges of a vertex of the edge (BFS distance >= 3).
class Apartness {
public:
    Apartness(const Model& model, const std::vector<Edge>& edges);
    bool farApart(const Edge& e, const Triangle& t) const {
        return nx_ > 0 ? gridApart(e.p, t) && gridApart(e.q, t) : meshApart(e.p, t) && meshApart(e.q, t);
    }
    // A group of triangles whose edges are all near the triangles of another group, and the
    // other way round, is dismissed whole. Sufficient tests: on a grid, every corner of one group
    // within 2 rows and 2 columns of every corner of the other (their spans); otherwise, each
    // triangle of one sharing a corner with each of the other (every corner within 2 edges).
    using Span = std::array<int, 4>;  // rows and columns of a group's corners: {min, max, min, max}
    bool grid() const { return nx_ > 0; }
    Span span(Index t0, int n) const;  // grid models: triangles t0 .. t0 + n - 1
    static bool spansNear(const Span& a, const Span& b) {
        return b[1] - a[0] <= 2 && a[1] - b[0] <= 2 && b[3] - a[2] <= 2 && a[3] - b[2] <= 2;
    }
    bool cornersShared(Index a0, int na, Index b0, int nb) const;

private:
    bool gridApart(Index u, const Triangle& t) const;
    bool meshApart(Index u, const Triangle& t) const;
    const std::vector<Triangle>& tris_;
    int nx_ = 0;
    std::vector<int> row_, col_;          // grid models: each particle's row and column
    // Non-grid models: the vertices within 2 mesh edges of v (v itself included), sorted, are
    // ring_[ringStart_[v] .. ringStart_[v + 1]).
    std::vector<Index> ringStart_, ring_;
};

}  // namespace cloth::crossings
