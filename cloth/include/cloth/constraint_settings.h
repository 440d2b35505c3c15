#pragma once
// The cloth's constraints as settings (constraints.h applies them): a public struct with its
// defaults, and its text form "tether=0.02,stretch_limit=0.1" through a key table of its fields
// (constraintKeys(); --help and the README's table print them after the solvers').

#include <string>
#include <string_view>
#include <vector>

#include "cloth/key_table.h"
#include "cloth/types.h"

namespace cloth {

struct Constraints {
    Scalar tether = 0;        // tethers: no particle farther from its nearest pin than (1 + tether) times at rest (0 = off)
    Scalar stretchLimit = 0;  // the stretch limit: max stretch of a spring, 0.1 = 10% (0 = off)
    int stretchPasses = 4;    // its Gauss-Seidel passes

    bool any() const { return tether > 0 || stretchLimit > 0; }
    // "tether=0.02,stretch_limit=0.1" with the keys that differ from the defaults ("" for none);
    // parseConstraints reads it back.
    std::string describe() const;
};

// Parses "key=value[,key=value...]" ("" = no constraints). Returns false and sets *error (naming
// the key and value) on an unknown key or a bad value.
bool parseConstraints(std::string_view spec, Constraints& out, std::string* error);
// Sets one key from its text, with the same rules; on failure `c` is unchanged.
bool setConstraint(Constraints& c, std::string_view key, std::string_view value, std::string* error);
// An empty string when every key is in range, else what is wrong.
std::string validate(const Constraints& c);
// The same from a number (a scene's JSON number).
bool setConstraint(Constraints& c, std::string_view key, double value, std::string* error);

using ConstraintKey = Key<Constraints>;
const std::vector<ConstraintKey>& constraintKeys();

}  // namespace cloth
