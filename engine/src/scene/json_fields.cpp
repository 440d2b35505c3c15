#include "scene/json_fields.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace engine {

nlohmann::json JsonFields::parseFile(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ConfigError(file + ": cannot open file");
    // Configuration files are small; a huge one is a mistake, not a scene.
    constexpr std::streamsize kMaxBytes = 16 << 20;
    std::string text;
    text.resize(kMaxBytes + 1);
    in.read(text.data(), kMaxBytes + 1);
    if (in.bad()) throw ConfigError(file + ": cannot read file");
    if (in.gcount() > kMaxBytes) throw ConfigError(file + ": file is larger than 16 MiB");
    text.resize(static_cast<std::size_t>(in.gcount()));
    return parseText(text, file);
}

nlohmann::json JsonFields::parseText(const std::string& text, const std::string& file) {
    try {
        return nlohmann::json::parse(text, nullptr, true, /*ignore_comments=*/false);
    } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e999
        throw ConfigError(file + ": not valid JSON: " + e.what());
    }
}

const nlohmann::json& JsonFields::emptyObject() {
    static const nlohmann::json empty = nlohmann::json::object();
    return empty;
}

void JsonFields::fail(const std::string& field, const nlohmann::json& value,
                      const std::string& why) const {
    std::string shown = value.dump();
    if (shown.size() > 60) shown = shown.substr(0, 57) + "...";
    throw ConfigError(file_ + ": " + field + " = " + shown + ": " + why);
}

void JsonFields::allowOnly(std::initializer_list<const char*> known) const {
    for (auto it = obj_.begin(); it != obj_.end(); ++it) {
        bool ok = false;
        for (const char* k : known) ok = ok || it.key() == k;
        if (!ok) {
            std::string list;
            for (const char* k : known) list += std::string(list.empty() ? "" : ", ") + k;
            fail(pathOf(it.key().c_str()), it.value(), "unknown field (known: " + list + ")");
        }
    }
}

double JsonFields::number(const char* key, double fallback, double min, double max) const {
    if (!obj_.contains(key)) return fallback;
    const auto& v = obj_.at(key);
    if (!v.is_number()) fail(pathOf(key), v, "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(pathOf(key), v, "must be finite");
    if (d < min || d > max) {
        std::ostringstream s;
        s << "must be in [" << min << ", " << max << "]";
        fail(pathOf(key), v, s.str());
    }
    return d;
}

int JsonFields::integer(const char* key, int fallback, int min, int max) const {
    if (!obj_.contains(key)) return fallback;
    const auto& v = obj_.at(key);
    if (!v.is_number_integer()) fail(pathOf(key), v, "must be an integer");
    const auto i = v.get<long long>();
    if (i < min || i > max)
        fail(pathOf(key), v, "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    return static_cast<int>(i);
}

bool JsonFields::boolean(const char* key, bool fallback) const {
    if (!obj_.contains(key)) return fallback;
    const auto& v = obj_.at(key);
    if (!v.is_boolean()) fail(pathOf(key), v, "must be true or false");
    return v.get<bool>();
}

std::string JsonFields::string(const char* key, const std::string& fallback) const {
    if (!obj_.contains(key)) return fallback;
    const auto& v = obj_.at(key);
    if (!v.is_string()) fail(pathOf(key), v, "must be a string");
    return v.get<std::string>();
}

std::string JsonFields::oneOf(const char* key, const std::string& fallback,
                              std::initializer_list<const char*> choices) const {
    const std::string s = string(key, fallback);
    std::string list;
    for (const char* c : choices) {
        if (s == c) return s;
        list += std::string(list.empty() ? "" : ", ") + c;
    }
    fail(pathOf(key), obj_.at(key), "must be one of: " + list);
}

std::array<double, 3> JsonFields::vec3(const char* key, std::array<double, 3> fallback, double min,
                                       double max) const {
    if (!obj_.contains(key)) return fallback;
    const auto& v = obj_.at(key);
    if (!v.is_array() || v.size() != 3) fail(pathOf(key), v, "must be an array of 3 numbers");
    std::array<double, 3> out{};
    for (int i = 0; i < 3; ++i) {
        const std::string field = pathOf(key) + "[" + std::to_string(i) + "]";
        if (!v[i].is_number()) fail(field, v[i], "must be a number");
        out[i] = v[i].get<double>();
        if (!std::isfinite(out[i])) fail(field, v[i], "must be finite");
        if (out[i] < min || out[i] > max) {
            std::ostringstream s;
            s << "must be in [" << min << ", " << max << "]";
            fail(field, v[i], s.str());
        }
    }
    return out;
}

JsonFields JsonFields::child(const char* key) const {
    if (!obj_.contains(key)) return JsonFields(file_, emptyObject(), pathOf(key));
    return JsonFields(file_, obj_.at(key), pathOf(key));
}

}  // namespace engine
