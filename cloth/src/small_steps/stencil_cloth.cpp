#include "small_steps/stencil_cloth.h"

#include <algorithm>

#include "kangcho/stencil.h"

namespace cloth {

namespace {

// Whether the model's triangles are the grid's, two per quad with alternating diagonals, as
// Model::fromGrid lays them (their corners as sets: the air does not depend on the order).
bool gridTriangles(const Model& model, int nx, int ny) {
    const auto& tris = model.triangles();
    if (tris.size() != std::size_t(2 * (nx - 1) * (ny - 1))) return false;
    auto same = [](Triangle a, Triangle b) {
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        return a == b;
    };
    std::size_t t = 0;
    for (int r = 0; r + 1 < ny; ++r)
        for (int c = 0; c + 1 < nx; ++c, t += 2) {
            const Index p = Index(r) * nx + c, e = p + 1, s = p + nx, d = p + nx + 1;
            const bool even = (r + c) % 2 == 0;
            if (!same(tris[t], even ? Triangle{p, s, d} : Triangle{p, s, e}) ||
                !same(tris[t + 1], even ? Triangle{p, e, d} : Triangle{e, s, d}))
                return false;
        }
    return true;
}

}  // namespace

std::string StencilCloth::build(const Model& model) {
    nx = model.gridNx(), ny = model.gridNy(), n = model.particleCount();
    modelId = model.id();
    if (nx < 2 || ny < 2 || !gridTriangles(model, nx, ny)) return "the model is not a grid laid out as Model::fromGrid lays it";
    offsets = springFamilies(model);
    if (offsets.empty()) return "the model's springs do not fall into a few constant index offsets";
    pad = std::max(offsets.back(), nx + 1);
    k.assign(offsets.size(), {});
    rest.assign(offsets.size(), {});
    for (std::size_t f = 0; f < offsets.size(); ++f) k[f].assign(n, pad), rest[f].assign(n, pad);
    for (const Spring& s : model.springs()) {
        const int lo = int(std::min(s.i, s.j)), d = int(std::max(s.i, s.j)) - lo;
        const auto f = std::size_t(std::lower_bound(offsets.begin(), offsets.end(), d) - offsets.begin());
        k[f].at()[lo] = float(s.k);
        rest[f].at()[lo] = float(s.rest);
    }
    invMass.assign(n, pad);
    for (int i = 0; i < n; ++i) invMass.at()[i] = float(1 / model.masses()[i]);
    quadValid.assign(n, pad), quadEven.assign(n, pad);
    for (int r = 0; r + 1 < ny; ++r)
        for (int c = 0; c + 1 < nx; ++c) {
            quadValid.at()[r * nx + c] = 1;
            quadEven.at()[r * nx + c] = (r + c) % 2 == 0 ? 1.0f : 0.0f;
        }
    return {};
}

void StencilState::assign(const StencilCloth& cloth) {
    x.assign(cloth.n, cloth.pad);
    v.assign(cloth.n, cloth.pad);
    spring.assign(cloth.offsets.size(), {});
    for (Vec3Field& f : spring) f.assign(cloth.n, cloth.pad);
    for (Vec3Field& c : corner) c.assign(cloth.n, cloth.pad);
    scratch.assign(cloth.n, cloth.pad);
}

}  // namespace cloth
