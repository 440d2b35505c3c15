#pragma once
// Bullet's btSoftBody cloth built from a cloth::Model: the same particles, masses, springs (as
// links) and pins, stepped by Bullet's own solver. The peer our users would pick instead.

#include <memory>
#include <vector>

#include "cloth/model.h"
#include "cloth/system.h"

namespace peer {

class BulletCloth {
public:
    // `iterations`: Bullet's position-solver iterations (m_cfg.piterations; Bullet's default is 1).
    // Link stiffness kLST is Bullet's [0, 1] coefficient (1: as stiff as its solver allows).
    BulletCloth(const cloth::Model& model, const cloth::State& state, const std::vector<cloth::Pin>& pins,
                int iterations, double linkStiffness = 1.0);
    ~BulletCloth();
    void step(double h);
    void positions(cloth::Points& x) const;
    // One step of h from `state` (its positions and velocities become Bullet's nodes'): the pinned
    // particles moved to their targets with their velocities (kinematic), `external` (per
    // particle, or null) added as a force on the free ones; Bullet's result back into `state`.
    void step(double h, const std::vector<cloth::Pin>& pins, const cloth::Points* external, cloth::State& state);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace peer
