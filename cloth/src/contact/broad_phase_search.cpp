// The broad phase's search for self pairs (broad_phase.h), split for threads. The top of the
// tree's walk (serial, a few nodes' boxes and cones) cuts it into tasks: the walk of one node, or
// of two, each of at most 1/kTaskShare of the grid's cells. Task k runs in stripe k mod stripes,
// on the loops' threads: it walks its nodes and searches the two leaves it reaches (the cells'
// boxes, the primitives' boxes, the Keep test of each candidate), writing only its stripe's
// visits and pairs and reading boxes made beforehand (refit, with loops on several threads).
// The tasks' visits are then gathered in the tasks' order, which is the whole walk's: the same
// pairs, in the same order, as one thread's search.
//
// Past `most` candidates the search stops. One thread stops at the first visit with more than
// `most` before it. A stripe stops once its own visits hold more than `most`: every visit before
// the first such stop was searched, and the sum of all exceeds `most` exactly when one thread's
// search would, so the answer and the count returned are the same.

#include <algorithm>

#include "contact/broad_phase.h"

namespace cloth::contact {

namespace {
constexpr int kTaskShare = 32;
}  // namespace

std::size_t BroadPhase::selfPairs(std::vector<Pair>& out, std::size_t most, const Keep& keep, ParallelFor* loops) {
    out.clear();
    plan();
    const int stripes = parallel(loops) ? 2 * loops->threads() : 1;
    if (int(stripes_.size()) < stripes) stripes_.resize(std::size_t(stripes));
    forChunks(loops, stripes, [&](int begin, int end) {
        for (int s = begin; s < end; ++s) runStripe(s, stripes, most, keep);
    });
    return gatherTasks(out, most);
}

int BroadPhase::cellsOf(int n) const {
    const Node& node = nodes_[std::size_t(n)];
    return (node.c1 - node.c0) * (node.r1 - node.r0);
}

// Whether a node's pairs within itself are left out: a flat node's, or a leaf's (all within the
// springs' reach).
bool BroadPhase::skipSelf(int n) const { return nodes_[std::size_t(n)].cosHalf > kFlat || nodes_[std::size_t(n)].leaf(); }

// Whether two nodes' pairs are left out: their boxes apart, every pair within the springs' reach,
// or one flat patch.
bool BroadPhase::skipCross(int a, int b) const {
    const Node &A = nodes_[std::size_t(a)], &B = nodes_[std::size_t(b)];
    if (!A.box.overlaps(B.box)) return true;
    const int span = std::max(std::max(A.c1, B.c1) - std::min(A.c0, B.c0), std::max(A.r1, B.r1) - std::min(A.r0, B.r0));
    if (span <= kExcludedCells) return true;  // every pair within the springs' reach
    const bool adjacent = A.c0 <= B.c1 && B.c0 <= A.c1 && A.r0 <= B.r1 && B.r0 <= A.r1;
    // Two adjacent nodes whose joint cone is flat are one flat patch. The joint cone is no
    // narrower than either node's (up to rounding, far under kConeRounding): when one is not
    // flat, neither is it, and it is not computed.
    return adjacent && std::min(A.cosHalf, B.cosHalf) > kFlat - kConeRounding &&
           mergedWithin(A.axis, A.cosHalf, A.partner, B.axis, B.cosHalf, B.partner, kFlat);
}

// Which of two nodes the walk splits: the larger, or the one that is not a leaf.
bool BroadPhase::splitsFirst(int a, int b) const {
    const Node &A = nodes_[std::size_t(a)], &B = nodes_[std::size_t(b)];
    return !A.leaf() && (B.leaf() || cellsOf(a) >= cellsOf(b));
}

// The tree's walk, in its order, from node n's own pairs (walkSelf) or from nodes a and b's
// (walkCross), down to the nodes `to` cuts at, which it hands on: to.at(n, -1) or to.at(a, b).
// Planning cuts at taskCells_ and makes tasks; a stripe cuts at the leaves and searches them,
// until to.stopped(). One walk for both keeps the tasks' order the whole walk's.
template <class To>
void BroadPhase::walkSelf(int n, To& to) {
    if (skipSelf(n)) return;
    if (to.cuts(n)) return to.at(n, -1);
    const Node& node = nodes_[std::size_t(n)];
    for (int i = 0; i < 4 && node.child[i] >= 0; ++i) {
        walkSelf(node.child[i], to);
        for (int j = i + 1; j < 4 && node.child[j] >= 0; ++j) walkCross(node.child[i], node.child[j], to);
    }
}

template <class To>
void BroadPhase::walkCross(int a, int b, To& to) {
    if (to.stopped() || skipCross(a, b)) return;
    if (to.cuts(a) && to.cuts(b)) return to.at(a, b);
    const bool splitA = splitsFirst(a, b);
    for (int c : nodes_[std::size_t(splitA ? a : b)].child)
        if (c >= 0) walkCross(splitA ? c : a, splitA ? b : c, to);
}

// The walk's top: a node of at most taskCells_ cells is a task.
struct BroadPhase::Planner {
    BroadPhase& broad;
    bool cuts(int n) const { return broad.cellsOf(n) <= broad.taskCells_; }
    void at(int a, int b) { broad.tasks_.push_back({a, b}); }
    bool stopped() const { return false; }
};

// A task's walk in its stripe: each two leaves searched as it reaches them, until the stripe's
// visits hold more than `most` candidates.
struct BroadPhase::Walker {
    BroadPhase& broad;
    Stripe& stripe;
    bool cuts(int n) const { return broad.nodes_[std::size_t(n)].leaf(); }
    void at(int a, int b) {
        Visit v;
        v.a = a, v.b = b;
        broad.search(v, stripe);
        stripe.found += v.found;
        stripe.visits.push_back(v);
    }
    bool stopped() const { return stripe.found > stripe.most; }
};

void BroadPhase::plan() {
    tasks_.clear();
    taskCells_ = std::max(4, (nx_ - 1) * (ny_ - 1) / kTaskShare);
    Planner planner{*this};
    if (!nodes_.empty()) walkSelf(0, planner);
}

// Stripe s's tasks (s, s + stripes, ...), until its visits hold more than `most` candidates.
void BroadPhase::runStripe(int s, int stripes, std::size_t most, const Keep& keep) {
    Stripe& stripe = stripes_[std::size_t(s)];
    stripe.pairs.clear(), stripe.visits.clear(), stripe.found = 0, stripe.most = most, stripe.keep = &keep;
    Walker walker{*this, stripe};
    for (std::size_t k = std::size_t(s); k < tasks_.size(); k += std::size_t(stripes)) {
        Task& t = tasks_[k];
        t.stripe = s, t.begin = stripe.visits.size();
        if (!walker.stopped()) t.b < 0 ? walkSelf(t.a, walker) : walkCross(t.a, t.b, walker);
        t.end = stripe.visits.size();
    }
}

// Two leaves' kept pairs: searched and kept at their first meeting since the refit (the boxes
// and so the candidates are the same until the next), reused after (searched_ is only read here).
// Leaves none of whose cells meet have none, which is found again faster than it is looked up.
void BroadPhase::search(Visit& v, Stripe& stripe) {
    Meet meet;
    if (!cellsMeet(v.a, v.b, meet)) return;
    v.met = true;
    if (const auto at = searched_.find((std::uint64_t(v.a) << 32) | std::uint32_t(v.b)); at != searched_.end()) {
        v.cached = true, v.found = at->second.found, v.begin = at->second.begin, v.end = at->second.end;
        return;
    }
    stripe.candidates.clear();
    fresh(nodes_[std::size_t(v.a)]), fresh(nodes_[std::size_t(v.b)]);
    leafPairs(nodes_[std::size_t(v.a)], nodes_[std::size_t(v.b)], meet, stripe.candidates);
    v.found = stripe.candidates.size(), v.begin = stripe.pairs.size();
    for (Pair& p : stripe.candidates)
        if ((*stripe.keep)(p)) stripe.pairs.push_back(p);
    v.end = stripe.pairs.size();
}

// The tasks' visits' pairs into `out` in the walk's order, each newly searched two leaves' kept
// pairs into searched_; stops after the visit that takes the candidates past `most`. Returns the
// candidates up to there.
std::size_t BroadPhase::gatherTasks(std::vector<Pair>& out, std::size_t most) {
    std::size_t found = 0;
    for (const Task& t : tasks_) {
        const Stripe& stripe = stripes_[std::size_t(t.stripe)];
        for (std::size_t k = t.begin; k < t.end; ++k) {
            if (found > most) return found;
            const Visit& v = stripe.visits[k];
            found += v.found;
            if (!v.met) continue;
            if (v.cached) {
                out.insert(out.end(), keptPairs_.begin() + std::ptrdiff_t(v.begin), keptPairs_.begin() + std::ptrdiff_t(v.end));
                continue;
            }
            Searched& s = searched_[(std::uint64_t(v.a) << 32) | std::uint32_t(v.b)];
            s.begin = keptPairs_.size(), s.found = v.found;
            keptPairs_.insert(keptPairs_.end(), stripe.pairs.begin() + std::ptrdiff_t(v.begin),
                              stripe.pairs.begin() + std::ptrdiff_t(v.end));
            s.end = keptPairs_.size();
            out.insert(out.end(), keptPairs_.begin() + std::ptrdiff_t(s.begin), keptPairs_.end());
        }
        if (found > most) return found;
    }
    return found;
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


}  // namespace cloth::contact
