#include "cloth/key_table.h"

#include <charconv>
#include <cmath>

namespace cloth {

std::string shortestText(double v) {
    for (int p = 1; p <= 17; ++p) {
        std::ostringstream t;
        t.precision(p);
        t << v;
        if (std::stod(t.str()) == v) return t.str();
    }
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

bool failWith(std::string* error, const std::string& message) {
    if (error) *error = message;
    return false;
}

std::string KeyRow::range() const {
    if (type == Type::Choice) {
        std::string out;
        for (const std::string& c : choices) out += (out.empty() ? "" : "|") + c;
        return out;
    }
    auto bound = [this](double v) { return type == Type::Integer ? std::to_string(int(v)) : shortestText(v); };
    return std::string(minOpen ? "(" : "[") + bound(min) + ", " + bound(max) + (maxOpen ? ")" : "]");
}

bool KeyRow::inRange(double v) const {
    if (type == Type::Choice) return true;
    return (minOpen ? v > min : v >= min) && (maxOpen ? v < max : v <= max);
}

std::string KeyRow::text(double v) const {
    if (type == Type::Choice) return choices[std::size_t(v)];
    if (type == Type::Integer) return std::to_string(int(v));
    return shortestText(v);
}

namespace {

bool readWord(const KeyRow& key, std::string_view text, double& value) {
    for (std::size_t i = 0; i < key.choices.size(); ++i)
        if (text == key.choices[i]) return value = double(i), true;
    // Switches also take true/false and 1/0.
    if (key.choices.size() == 2 && key.choices[0] == "on") {
        if (text == "true" || text == "1") return value = 0, true;
        if (text == "false" || text == "0") return value = 1, true;
    }
    return false;
}

bool readInteger(std::string_view text, double& value) {
    int v = 0;
    auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || p != text.data() + text.size()) return false;
    value = v;
    return true;
}

bool readReal(std::string_view text, double& value) {
    auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc() && p == text.data() + text.size() && std::isfinite(value);
}

}  // namespace

bool KeyRow::read(std::string_view text, double& value) const {
    double v = 0;
    const bool ok = type == Type::Choice ? readWord(*this, text, v)
                    : type == Type::Integer ? readInteger(text, v)
                                            : readReal(text, v);
    if (!ok || !inRange(v)) return false;
    value = v;
    return true;
}

bool forEachItem(std::string_view list, const char* what, std::string* error,
                 const std::function<bool(std::string_view, std::string_view)>& set) {
    while (!list.empty()) {
        const auto comma = list.find(',');
        const std::string_view item = list.substr(0, comma);
        list = comma == std::string_view::npos ? "" : list.substr(comma + 1);
        const auto eq = item.find('=');
        if (eq == std::string_view::npos)
            return failWith(error, std::string(what) + " '" + std::string(item) + "' is not key=value");
        if (!set(item.substr(0, eq), item.substr(eq + 1))) return false;
    }
    return true;
}

}  // namespace cloth
