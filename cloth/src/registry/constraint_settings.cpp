// The cloth's constraints' keys (tether, stretch_limit, stretch_passes) as a key table, and the
// parser, validation and describe() as loops over it.

#include "cloth/constraint_settings.h"

#include <algorithm>
#include <cmath>

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

namespace {

// The key `key`, or null with *error naming what is wrong.
const ConstraintKey* keyOf(std::string_view key, std::string* error) {
    const auto& rows = constraintKeys();
    const auto k = std::find_if(rows.begin(), rows.end(), [&](const ConstraintKey& r) { return key == r.name; });
    if (k != rows.end()) return &*k;
    std::string known;
    for (const ConstraintKey& r : rows) known += (known.empty() ? "" : ", ") + std::string(r.name);
    failWith(error, "constraints have no key '" + std::string(key) + "' (known: " + known + ")");
    return nullptr;
}

bool badValue(const ConstraintKey& k, std::string_view value, std::string* error) {
    return failWith(error, "constraint " + std::string(k.name) + " has a bad value '" + std::string(value) +
                               "' (allowed: " + k.range() + ")");
}

}  // namespace

bool setConstraint(Constraints& c, std::string_view key, std::string_view value, std::string* error) {
    const ConstraintKey* k = keyOf(key, error);
    if (!k) return false;
    double v = 0;
    if (!k->read(value, v)) return badValue(*k, value, error);
    k->set(c, v);
    return true;
}

bool setConstraint(Constraints& c, std::string_view key, double value, std::string* error) {
    const ConstraintKey* k = keyOf(key, error);
    if (!k) return false;
    const bool whole = std::isfinite(value) && std::floor(value) == value;
    if ((k->type == KeyRow::Type::Integer && !whole) || !k->inRange(value)) return badValue(*k, shortestText(value), error);
    k->set(c, value);
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
