// The contact stage's proximity pushes (cloth/contact.h).

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/geometry.h"
#include "contact/work.h"

namespace cloth {

using namespace contact;

// Moves the targets of n particles (weights w_k on the primitive's side, signs folded in) so that
// their weighted sum gains `gap` along `normal` (position-based: inverse masses as weights).
void ContactStage::Work::pushApart(const Index* ids, const Scalar* weights, int n, const Vec3& normal, Scalar gap) {
    Scalar denom = 0;
    for (int k = 0; k < n; ++k) denom += invMass[ids[k]] * weights[k] * weights[k];
    if (denom <= 0 || gap <= 0) return;
    const Scalar lambda = std::min(gap, thickness) / denom;
    for (int k = 0; k < n; ++k) push.col(ids[k]) += (lambda * invMass[ids[k]] * weights[k]) * normal;
}

// Proximity: self pairs and edges near a capsule that would end the sub-interval closer than
// `thickness` are pushed apart along the direction that separates them now. A self pair whose
// gap's lower bound less its approach on the way to the targets (need) clears `thickness` cannot
// end that close and is not measured; a measured pair's gap is kept for its bounds.
void ContactStage::Work::separate() {
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (gapBound(k) - approach(k, [&](int, Index i) { return need[i]; }) >= thickness + kSlack) continue;
        const Closest c = closestNow(k);
        measured(k, c.distance, c.normal);
        if (c.distance <= 0) continue;
        pushApart(ids[k].data(), c.weights.data(), 4, c.normal, thickness - separation(k, c, target).dot(c.normal));
    }
    for (const Near& n : near) {
        if (n.solid->shape != Collider::Shape::Capsule) continue;
        const auto [a, b] = axisOf(*n.solid);
        for (Index e : n.edges) {
            const Index i = (*edges)[e][0], j = (*edges)[e][1];
            const auto now = contact::closestSegments(y.col(i), y.col(j), a, b);
            const Vec3 p = (1 - now.s) * y.col(i) + now.s * y.col(j), q = (1 - now.t) * a + now.t * b;
            if (now.distance <= 0) continue;
            const Vec3 normal = (p - q) / now.distance;
            const Vec3 pt = (1 - now.s) * target.col(i) + now.s * target.col(j);
            const Index ids[2] = {i, j};
            const Scalar ws[2] = {1 - now.s, now.s};
            pushApart(ids, ws, 2, normal, n.solid->radius + thickness - (pt - q).dot(normal));
        }
    }
}

}  // namespace cloth
