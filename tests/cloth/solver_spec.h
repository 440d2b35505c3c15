#pragma once
// The cloth tests' one way to make a solver from its spec ("name:key=value,..."): a spec that does
// not parse fails the calling test, naming the spec and why.

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "cloth/solver.h"
#include "cloth/solver_config.h"
#include "cloth/solver_config.h"

inline std::unique_ptr<cloth::Solver> solverOf(const std::string& spec) {
    cloth::SolverConfig config;
    std::string error;
    EXPECT_TRUE(cloth::parseSolverConfig(spec, config, &error)) << spec << ": " << error;
    return cloth::makeSolver(config);
}
