// The cloth's constraints' keys (tether, stretch_limit, stretch_passes) as a key table, and the
// parser, validation and describe() of constraints.h as loops over it.

#include "registry/constraint_keys.h"

#include <algorithm>

namespace cloth {

const std::vector<ConstraintKey>& constraintKeys() {
    using C = Constraints;
    using key = KeysOf<C>;
    static const std::vector<ConstraintKey> rows = {
        key::real("tether", &C::tether, 0, 10, false, true,
                  "tethers (long-range attachments): no particle farther from its nearest pin than (1 + tether) "
                  "times at rest (0 = off)"),
        key::real("stretch_limit", &C::stretchLimit, 0, 10, false, true,
                  "the stretch limit: no spring longer than (1 + stretch_limit) times its rest length (0 = off)"),
        key::integer("stretch_passes", &C::stretchPasses, 1, 1000, "Gauss-Seidel passes of the stretch limit"),
    };
    return rows;
}

bool setConstraint(Constraints& c, std::string_view key, std::string_view value, std::string* error) {
    const auto& rows = constraintKeys();
    const auto k = std::find_if(rows.begin(), rows.end(), [&](const ConstraintKey& r) { return key == r.name; });
    if (k == rows.end()) {
        std::string known;
        for (const ConstraintKey& r : rows) known += (known.empty() ? "" : ", ") + std::string(r.name);
        return failWith(error, "constraints have no key '" + std::string(key) + "' (known: " + known + ")");
    }
    double v = 0;
    if (!k->read(value, v))
        return failWith(error, "constraint " + std::string(key) + " has a bad value '" + std::string(value) +
                                   "' (allowed: " + k->range() + ")");
    k->set(c, v);
    return true;
}

bool parseConstraints(std::string_view spec, Constraints& out, std::string* error) {
    Constraints c;
    if (!forEachItem(spec, "constraint", error,
                     [&](std::string_view key, std::string_view value) { return setConstraint(c, key, value, error); }))
        return false;
    out = c;
    return true;
}

std::string validate(const Constraints& c) {
    for (const ConstraintKey& k : constraintKeys())
        if (!k.inRange(k.get(c))) return std::string("constraint ") + k.name + " = " + k.text(c) + " must be in " + k.range();
    return {};
}

std::string Constraints::describe() const {
    const Constraints defaults;
    std::string out;
    for (const ConstraintKey& k : constraintKeys())
        if (k.get(*this) != k.get(defaults)) {
            if (!out.empty()) out += ',';
            out.append(k.name).append("=").append(k.text(*this));
        }
    return out;
}

}  // namespace cloth
