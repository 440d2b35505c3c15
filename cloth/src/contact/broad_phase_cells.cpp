// The broad phase's test of two leaves' cells (broad_phase.h): which two cells can hold a pair far
// enough apart to be searched, known from the grid alone when the tree is built, and which of those
// have boxes that meet in a step.

#include <algorithm>
#include <array>
#include <cstdlib>

#include "contact/broad_phase.h"

namespace cloth::contact {

namespace {

// The 16 offsets (dr, dc) of a cell two cells from another (the larger of |dr| and |dc| is 2),
// numbered row by row: -1 for the others.
constexpr std::array<std::array<int, 5>, 5> kTwoApartBits = {{
    {0, 1, 2, 3, 4},
    {5, -1, -1, -1, 6},
    {7, -1, -1, -1, 8},
    {9, -1, -1, -1, 10},
    {11, 12, 13, 14, 15},
}};

int twoApartBit(int dr, int dc) {
    return std::abs(dr) > 2 || std::abs(dc) > 2 ? -1 : kTwoApartBits[std::size_t(dr + 2)][std::size_t(dc + 2)];
}

}  // namespace

// For each cell and each cell two cells from it: whether their primitives hold a pair far enough
// apart to be searched (far). Most do not (every corner of one within kExcludedCells of some
// corner of the other), and their boxes meet whenever the cloth bends: cellsMeet skips them.
void BroadPhase::twoApartPairs() {
    const int cells = (nx_ - 1) * (ny_ - 1);
    twoApart_.assign(cells, 0);
    auto anyPair = [&](int a, int b) {
        for (Index v : cellVertices_[a])
            for (Index t : cellTriangles_[b])
                if (farTriangle(v, t)) return true;
        for (Index e : cellEdges_[a])
            for (Index f : cellEdges_[b])
                if (farEdges(e, f)) return true;
        return false;
    };
    for (int r = 0; r < ny_ - 1; ++r)
        for (int c = 0; c < nx_ - 1; ++c)
            for (int dr = -2; dr <= 2; ++dr)
                for (int dc = -2; dc <= 2; ++dc) {
                    const int bit = twoApartBit(dr, dc), rb = r + dr, cb = c + dc;
                    if (bit < 0 || rb < 0 || cb < 0 || rb >= ny_ - 1 || cb >= nx_ - 1) continue;
                    const int a = r * (nx_ - 1) + c, b = rb * (nx_ - 1) + cb;
                    if (anyPair(a, b) || anyPair(b, a)) twoApart_[a] |= std::uint16_t(1u << bit);
                }
}

// Whether cell a and the cell (dr, dc) from it (b less a: -dr, -dc) are far enough apart to hold a
// pair: more than two cells (within one, every corner of one lies within kExcludedCells of every
// corner of the other), or two with a far pair (twoApartPairs).
bool BroadPhase::apartPairs(int a, int dr, int dc) const {
    static_assert(kExcludedCells >= 2, "cells within one of each other are skipped");
    const int apart = std::max(std::abs(dr), std::abs(dc));
    return apart > 2 || (apart == 2 && (twoApart_[std::size_t(a)] >> twoApartBit(-dr, -dc)) & 1);
}

// Each leaf's cells, and for each leaf the leaves within two cells of it with the cells of the two
// that can hold a pair (apartPairs): found through each cell's leaf, in the band of two cells
// around the leaf.
void BroadPhase::nearLeaves() {
    const int w = nx_ - 1, h = ny_ - 1;
    leafCells_.assign(nodes_.size(), {-1, -1, -1, -1});
    nearLeaves_.assign(nodes_.size(), {});
    std::vector<int> leafOf(std::size_t(w * h), -1);
    for (int n : leaves_)
        eachCell(nodes_[std::size_t(n)], [&](const Cell& c) { leafCells_[std::size_t(n)][std::size_t(c.k)] = c.index, leafOf[std::size_t(c.index)] = n; });
    for (int a : leaves_) {
        const Node& A = nodes_[std::size_t(a)];
        auto& list = nearLeaves_[std::size_t(a)];
        for (int r = std::max(0, A.r0 - 2); r < std::min(h, A.r1 + 2); ++r)
            for (int c = std::max(0, A.c0 - 2); c < std::min(w, A.c1 + 2); ++c) {
                const int b = leafOf[std::size_t(r * w + c)];
                if (b == a || std::any_of(list.begin(), list.end(), [&](const auto& e) { return e.first == b; })) continue;
                std::uint16_t mask = 0;
                eachCell(A, [&](const Cell& ca) {
                    eachCell(nodes_[std::size_t(b)], [&](const Cell& cb) {
                        if (apartPairs(ca.index, ca.r - cb.r, ca.c - cb.c)) mask |= std::uint16_t(1u << (4 * ca.k + cb.k));
                    });
                });
                list.emplace_back(b, mask);
            }
    }
}

// The bits 4 ka + kb of leaves a and b's cells that can hold a pair (nearLeaves_).
std::uint16_t BroadPhase::farCells(int a, int b) const {
    for (const auto& [leaf, mask] : nearLeaves_[std::size_t(a)])
        if (leaf == b) return mask;
    std::uint16_t all = 0;
    const auto &ca = leafCells_[std::size_t(a)], &cb = leafCells_[std::size_t(b)];
    for (int ka = 0; ka < 4 && ca[std::size_t(ka)] >= 0; ++ka)
        for (int kb = 0; kb < 4 && cb[std::size_t(kb)] >= 0; ++kb) all |= std::uint16_t(1u << (4 * ka + kb));
    return all;
}

// Two cells' primitives can form a pair only if the cells can hold one (farCells) and the cells'
// boxes (each holding its triangles, and so the vertices and edges it owns) overlap. Tested once
// for each such two cells of leaves a and b (meet[ka][kb], a leaf has at most 2 x 2 cells), from
// the cells' boxes alone, before the leaves' edges and triangles have boxes (fresh): false if no
// two meet.
bool BroadPhase::cellsMeet(int a, int b, Meet& meet) const {
    meet = {};
    const auto &ca = leafCells_[std::size_t(a)], &cb = leafCells_[std::size_t(b)];
    bool any = false;
    for (unsigned bits = farCells(a, b); bits != 0; bits &= bits - 1) {
        const int bit = __builtin_ctz(bits), ka = bit >> 2, kb = bit & 3;
        const bool m = cellBox_[std::size_t(ca[std::size_t(ka)])].overlaps(cellBox_[std::size_t(cb[std::size_t(kb)])]);
        meet[std::size_t(ka)][std::size_t(kb)] = m;
        any = any | m;
    }
    return any;
}

}  // namespace cloth::contact
