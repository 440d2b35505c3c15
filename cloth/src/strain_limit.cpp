#include "cloth/strain_limit.h"

#include <cmath>
#include <cstdint>

namespace cloth {

int limitStretch(const Model& model, const std::vector<std::uint8_t>& pinned, Scalar maxStretch, int passes,
                 Scalar h, State& state) {
    const auto& mass = model.masses();
    const auto& springs = model.springs();
    const std::size_t nSprings = springs.size();
    // A spring's length changes only when one of its ends moves. So a pass needs to look only at
    // the springs one of whose ends moved since the spring was last looked at (the first pass:
    // all of them); every other spring is still within its limit, bit for bit, and the Gauss-
    // Seidel passes visit them without effect. The dirty set is a bitset in spring order: a
    // correction marks every spring at its moved ends, those after the current one are visited
    // later in this pass, those before it in the next, exactly as a pass over all springs would.
    static thread_local std::vector<Scalar> invMass, limit2;
    static thread_local std::vector<std::uint64_t> dirty;
    invMass.resize(mass.size());
    for (std::size_t i = 0; i < mass.size(); ++i) invMass[i] = pinned[i] ? 0 : 1 / mass[i];
    limit2.resize(nSprings);
    for (std::size_t s = 0; s < nSprings; ++s) {
        const Scalar limit = (1 + maxStretch) * springs[s].rest;
        limit2[s] = limit * limit;
    }
    const std::size_t words = (nSprings + 63) / 64;
    dirty.assign(words, ~std::uint64_t(0));
    if (nSprings % 64) dirty[words - 1] = (std::uint64_t(1) << (nSprings % 64)) - 1;

    const auto& adjStart = model.adjStart();
    const auto& adjSpring = model.adjSpring();
    auto markAround = [&](Index p) {
        for (Index k = adjStart[p]; k < adjStart[p + 1]; ++k) {
            const Index t = adjSpring[k];
            dirty[t >> 6] |= std::uint64_t(1) << (t & 63);
        }
    };
    Scalar* x = state.x.data();
    Scalar* v = state.v.data();
    const Scalar invH = 1 / h;
    // One spring: within its limit (the common case, a squared norm and a comparison), or its
    // ends pulled together to the limit, split by inverse mass. Returns whether it corrected.
    auto visit = [&](std::size_t s) {
        const Index i = springs[s].i, j = springs[s].j;
        const Scalar dx = x[3 * j] - x[3 * i], dy = x[3 * j + 1] - x[3 * i + 1], dz = x[3 * j + 2] - x[3 * i + 2];
        const Scalar L2 = dx * dx + dy * dy + dz * dz;
        if (L2 <= limit2[s] || L2 < Scalar(1e-24)) return false;
        const Scalar wi = invMass[i], wj = invMass[j];
        if (wi + wj == 0) return false;
        const Scalar L = std::sqrt(L2), limit = (1 + maxStretch) * springs[s].rest;
        const Scalar c = (L - limit) / (L * (wi + wj));  // total shortening, split by 1/m
        const Scalar d[3] = {c * dx, c * dy, c * dz};
        for (int a = 0; a < 3; ++a) {
            x[3 * i + a] += wi * d[a];
            x[3 * j + a] -= wj * d[a];
            v[3 * i + a] += wi * invH * d[a];
            v[3 * j + a] -= wj * invH * d[a];
        }
        if (wi != 0) markAround(i);
        if (wj != 0) markAround(j);
        return true;
    };
    int corrections = 0;
    for (int pass = 0; pass < passes; ++pass) {
        int thisPass = 0;
        for (std::size_t w = 0; w < words; ++w) {
            std::uint64_t todo = dirty[w];
            while (todo) {
                const int b = __builtin_ctzll(todo);
                dirty[w] &= ~(std::uint64_t(1) << b);
                thisPass += visit(64 * w + std::size_t(b));
                // Re-read: the visit may have marked later springs of this word.
                todo = b == 63 ? 0 : dirty[w] & (~std::uint64_t(0) << (b + 1));
            }
        }
        corrections += thisPass;
        if (thisPass == 0) break;
    }
    return corrections;
}

}  // namespace cloth
