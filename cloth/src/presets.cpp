#include "cloth/presets.h"

namespace cloth {

HangingFlag makeHangingFlag(const HangingFlagDesc& d) {
    GridDesc g;
    g.nx = d.nx;
    g.ny = d.ny;
    g.width = d.width;
    g.height = d.height;
    g.totalMass = d.totalMass;
    g.stiffness = d.stiffness;
    g.origin = d.poleTop;
    g.axisU = Vec3::UnitX();
    g.axisV = -Vec3::UnitY();
    Model model = Model::fromGrid(g);
    State state = State::atRest(model);
    std::vector<Pin> pins = pinColumn(model);
    return {std::move(model), std::move(state), std::move(pins)};
}

std::vector<Pin> pinColumn(const Model& model, const Vec3& offset, const Vec3& v) {
    std::vector<Pin> pins;
    const int nx = model.gridNx(), ny = model.gridNy();
    for (int r = 0; r < ny; ++r) {
        const Index p = r * nx;
        pins.push_back({p, model.restPositions().col(p) + offset, v});
    }
    return pins;
}

}  // namespace cloth
