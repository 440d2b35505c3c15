#pragma once
// What the live panel shows and what it asks for: plain data, so the runtime can fill and read
// them in builds without Dear ImGui.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "cloth/model.h"
#include "cloth/solver.h"
#include "engine/scene/command.h"

namespace engine {

// What the panel shows this frame; the runtime fills it.
struct PanelState {
    std::string scene;
    std::string antiAliasing;         // what runs ("post (auto on llvmpipe ...)")
    std::vector<std::string> scenes;  // the scenes to switch to
    std::string switchNote;           // non-empty: switching and restarting are off, and why
    bool hasFlag = false, hasAir = false;
    cloth::SolverConfig solver;
    cloth::Stiffness stiffness;
    double mass = 0;
    Eigen::Vector3d wind = Eigen::Vector3d::Zero();
    double airDensity = 0;
    double physicsHz = 0;
    bool paused = false;
    double simTime = 0;
    // The last finished frame: its phases' milliseconds (the profile's row), the flag's stretch,
    // the solver's iterations per step.
    std::vector<std::string> phases;
    std::vector<double> phaseMs;
    double p99Stretch = 0, maxStretch = 0, iterationsPerStep = 0;
    int crossings = -1, crossingsMax = 0;  // the last count's and the most in one (-1: not counted)
    std::string refusal;  // the last command refused, and why (empty: none)
};

// What the user asked for in the last frame.
struct PanelRequests {
    std::vector<Command> commands;
    std::vector<std::string> refusals;  // what the panel refused to ask for, and why
    std::string scene;  // switch to this scene (empty: stay)
    bool restart = false;
};

}  // namespace engine
