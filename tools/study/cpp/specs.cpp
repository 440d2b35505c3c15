#include "specs.h"

#include <cstdio>
#include <cstdlib>

#include "cloth/solver_config.h"

namespace study {

cloth::SolverConfig configOf(const std::string& spec, void (*tune)(cloth::MultigridTuning&)) {
    cloth::SolverConfig c;
    std::string error;
    if (!cloth::parseSolverConfig(spec, c, &error)) {
        std::fprintf(stderr, "cloth_study: solver spec '%s': %s\n", spec.c_str(), error.c_str());
        std::exit(2);
    }
    if (tune) {
        auto& m = c.get<cloth::MultigridSettings>();
        cloth::MultigridTuning t = cloth::settledTuning(m);
        tune(t);
        m.tuning = t;
    }
    return c;
}

cloth::Constraints constraintsOf(const std::string& spec) {
    cloth::Constraints c;
    std::string error;
    if (!cloth::parseConstraints(spec, c, &error)) {
        std::fprintf(stderr, "cloth_study: constraints '%s': %s\n", spec.c_str(), error.c_str());
        std::exit(2);
    }
    return c;
}

}  // namespace study
