#include "crossings/topology.h"

#include <algorithm>
#include <cstdlib>

namespace cloth::crossings {

namespace {

// Compressed rows of the mesh graph: the neighbours of v are nbr[start[v] .. start[v + 1]).
struct Graph { std::vector<Index> start, nbr; };

Graph meshGraph(int n, const std::vector<Edge>& edges) {
    Graph g;
    g.start.assign(n + 1, 0);
    for (const Edge& e : edges) {
        ++g.start[e.p + 1];
        ++g.start[e.q + 1];
    }
    for (int v = 0; v < n; ++v) g.start[v + 1] += g.start[v];
    g.nbr.resize(g.start[n]);
    std::vector<Index> fill(g.start.begin(), g.start.end() - 1);
    for (const Edge& e : edges) {
        g.nbr[fill[e.p]++] = e.q;
        g.nbr[fill[e.q]++] = e.p;
    }
    return g;
}

bool has(const Triangle& t, Index v) { return t[0] == v || t[1] == v || t[2] == v; }

}  // namespace

// Edge uv (u < v) is listed under the first triangle of model.triOf(u) (in increasing order)
// that has v: a pass over each u's triangles marks the v met, once to count the edges of each
// triangle, once to list them.
MeshEdges meshEdges(const Model& model) {
    const auto& tris = model.triangles();
    const auto& triStart = model.triStart();
    const auto& triOf = model.triOf();
    const Index n = model.particleCount();
    MeshEdges m;
    m.start.assign(tris.size() + 1, 0);
    std::vector<Index> mark(n, -1);
    auto pass = [&](auto&& list) {
        for (Index u = 0; u < n; ++u)
            for (Index j = triStart[u]; j < triStart[u + 1]; ++j)
                for (const Index v : tris[triOf[j]])
                    if (v > u && mark[v] != u) {
                        mark[v] = u;
                        list(triOf[j], Edge{u, v});
                    }
    };
    pass([&](Index t, const Edge&) { ++m.start[t + 1]; });
    for (std::size_t t = 0; t < tris.size(); ++t) m.start[t + 1] += m.start[t];
    m.edges.resize(m.start.back());
    std::vector<Index> fill(m.start.begin(), m.start.end() - 1);
    mark.assign(n, -1);
    pass([&](Index t, const Edge& e) { m.edges[fill[t]++] = e; });
    return m;
}

// Grid: rows and columns of particles. Otherwise: ring(v) = {v} + neighbours +
// their neighbours, sorted and unique.
Apartness::Apartness(const Model& model, const std::vector<Edge>& edges)
    : tris_(model.triangles()), nx_(model.gridNx()) {
    const int n = model.particleCount();
    if (nx_ > 0) {
        row_.resize(n);
        col_.resize(n);
        for (int i = 0; i < n; ++i) {
            row_[i] = i / nx_;
            col_[i] = i % nx_;
        }
        return;
    }
    const Graph g = meshGraph(n, edges);
    ringStart_.assign(1, 0);
    std::vector<Index> ring;
    for (Index v = 0; v < n; ++v) {
        ring.assign(1, v);
        for (Index k = g.start[v]; k < g.start[v + 1]; ++k) {
            const Index w = g.nbr[k];
            ring.push_back(w);
            ring.insert(ring.end(), g.nbr.begin() + g.start[w], g.nbr.begin() + g.start[w + 1]);
        }
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
        ring_.insert(ring_.end(), ring.begin(), ring.end());
        ringStart_.push_back(Index(ring_.size()));
    }
}

Apartness::Span Apartness::span(Index t0, int n) const {
    Span s = {row_[tris_[t0][0]], row_[tris_[t0][0]], col_[tris_[t0][0]], col_[tris_[t0][0]]};
    for (Index t = t0; t < t0 + n; ++t)
        for (const Index v : tris_[t])
            s = {std::min(s[0], row_[v]), std::max(s[1], row_[v]), std::min(s[2], col_[v]), std::max(s[3], col_[v])};
    return s;
}

bool Apartness::cornersShared(Index a0, int na, Index b0, int nb) const {
    for (Index a = a0; a < a0 + na; ++a)
        for (Index b = b0; b < b0 + nb; ++b)
            if (!has(tris_[b], tris_[a][0]) && !has(tris_[b], tris_[a][1]) && !has(tris_[b], tris_[a][2]))
                return false;
    return true;
}

// max(|row_u - row_w|, |col_u - col_w|) >= 3 for every corner w.
bool Apartness::gridApart(Index u, const Triangle& t) const {
    const int ru = row_[u], cu = col_[u];
    for (const Index w : t)
        if (std::abs(row_[w] - ru) < 3 && std::abs(col_[w] - cu) < 3) return false;
    return true;
}

// No corner w within 2 mesh edges of u.
bool Apartness::meshApart(Index u, const Triangle& t) const {
    const auto first = ring_.begin() + ringStart_[u], last = ring_.begin() + ringStart_[u + 1];
    for (const Index w : t)
        if (std::binary_search(first, last, w)) return false;
    return true;
}

}  // namespace cloth::crossings
