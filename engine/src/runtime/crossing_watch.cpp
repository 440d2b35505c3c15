#include "runtime/crossing_watch.h"

#include <algorithm>

namespace engine {

CrossingWatch::CrossingWatch(const SceneConfig& scene, const PoleMount& mount, bool ground)
    : mount_(mount), ground_(ground) {
    if (!flagDescOf(scene).onShell) {
        const int nx = scene.flag.nx;
        sleeve_.assign(std::size_t(scene.flag.nx * scene.flag.ny), 0);
        for (int r = 0; r < scene.flag.ny; ++r) sleeve_[std::size_t(r * nx)] = 1;
    }
}

void CrossingWatch::count(const Flag& flag, const RigidFrame& carrier, const cloth::Collider* body) {
    cloth::CrossingScene scene;
    const auto [a, b] = cloth::poleAxis(mount_);  // the pole's solid, as contact keeps the cloth out of it
    scene.capsules.push_back({carrier.point(a), carrier.point(b), mount_.radius});
    if (body) scene.boxes.push_back({body->center, body->rotation, body->halfExtents});
    if (ground_) scene.grounds.push_back({});
    const cloth::CrossingCounts c =
        cloth::countCrossings(flag.model(), flag.state().x, scene, sleeve_.empty() ? nullptr : &sleeve_);
    tally_.last = c.total();
    if (tally_.last > tally_.max) tally_.max = tally_.last, tally_.worst = c;
    cloth::CrossingCounts& m = tally_.most;
    m.poleEdges = std::max(m.poleEdges, c.poleEdges), m.selfEdges = std::max(m.selfEdges, c.selfEdges);
    m.bodyEdges = std::max(m.bodyEdges, c.bodyEdges), m.groundParticles = std::max(m.groundParticles, c.groundParticles);
    ++tally_.checks;
    tally_.withAny += tally_.last > 0;
}

}  // namespace engine
