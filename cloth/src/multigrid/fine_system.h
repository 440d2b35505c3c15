#pragma once
// The finest level's system, the linearized backward Euler step of every implicit solver here
// (system.h: W dv = b, J with eq. 17, W_ii with drag and implicit air, pinned particles
// eliminated): built once per step from the state, in the layout of the cloth's topology (banded
// springs on grids, gathered on meshes). Pinned particles are unknowns fixed at zero (their
// prescribed dv is already in their neighbours' b, as in the paper's step), so their rows are zero.

#include <memory>
#include <vector>

#include "banded_springs.h"
#include "cloth/solver.h"
#include "gathered_springs.h"
#include "level.h"

namespace cloth {

template <class T>
struct FineSystem {
    SpringSet<T> springs;   // meshes
    BandedSprings<T> band;  // grids
    std::vector<T> base;    // 6n: the spring-free part of W_ii (mass, drag, damping)
    std::vector<unsigned char> pinned;
    std::vector<T> pinDv;   // 3n: the pinned particles' prescribed change
    T h2 = 0;               // of the last build
    bool compressionRule = true;

    // Level 0's pattern (the model's springs) and the springs in the layout it allows.
    void prepare(const Model& model, Level<T>& L0);
    // W, W_ii^-1 and b of level 0 for the step's problem.
    void build(const StepProblem& problem, Level<T>& L0, ThreadPool& pool);
    // Level 0 as `fine` holds it (the same model's system in double), rounded: what the cycles
    // read (W, its block copy, W_ii^-1, the free rows, the pinned particles); b stays with fine.
    void roundFrom(const FineSystem<double>& fine, const Level<double>& from, Level<T>& L0, ThreadPool& pool);
};

}  // namespace cloth
