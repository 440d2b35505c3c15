#pragma once
// The multigrid tests' cloths (test_implicit_air.cpp, whitebox/test_multigrid.cpp): a stiff flag
// on a grid or as a mesh in a deformed, moving state, its step's input, the reference path's
// matrix of the free unknowns, and multigrid solvers with their tuning changed.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cloth/solver.h"
#include "cloth/solvers/multigrid_settings.h"
#include "physics_support.h"  // solverFor

namespace cloth::test {

struct Case {
    Model model;
    State state;
    std::vector<Pin> pins;
    Points external;
};

// A stiff flag (k 1e4, 0.3 kg) on a grid or the same surface as a mesh, in a deformed and moving
// state like a flag's (stretched 5% along its length, a wave across it, and a random ripple of
// `rough` times the spacing), its column 0 pinned to targets that move.
Case stiffCase(int nx, int ny, bool mesh, unsigned seed, Scalar rough = 0.01);

// A cloth of stiffCase: its grid sides, and whether it is the mesh of that grid.
struct Size {
    int nx, ny;
    bool mesh;
};

StepInput inputOf(const Case& c, Scalar h = 1.0 / 240);

// W of the reference path with pinned rows and columns zeroed: the matrix of the free unknowns,
// which is what multigrid's level 0 holds.
Eigen::MatrixXd referenceFreeMatrix(const Case& c, const LinearSystem& sys);

using Tune = std::function<void(MultigridTuning&)>;

// Settings with their settled tuning changed by `tune`.
MultigridSettings tuned(MultigridSettings s, const Tune& tune);

// dv of one step of `spec` (its tuning changed by `tune` when given) on the case.
Points stepDv(const std::string& spec, const Case& c, const Environment& env = {}, const Tune& tune = nullptr);

}  // namespace cloth::test
