#pragma once
// Strict reading of JSON configuration: every field is checked for type, range and finiteness,
// unknown fields are rejected, and every error names the file, the field path and the value.

#include <nlohmann/json.hpp>
#include <array>
#include <initializer_list>
#include <string>

#include "engine/scene/config_error.h"

namespace engine {

class JsonFields {
public:
    JsonFields(std::string file, const nlohmann::json& object, std::string path = {})
        : file_(std::move(file)), obj_(object), path_(std::move(path)) {
        if (!obj_.is_object()) fail(path_.empty() ? "(top level)" : path_, obj_, "must be an object");
    }
    // Loads and parses a file; errors name the file (and the line/column of a syntax error).
    static nlohmann::json parseFile(const std::string& file);
    // Parses text that came from `file` (the name is only used in messages).
    static nlohmann::json parseText(const std::string& text, const std::string& file);

    // Rejects any field not in `known`.
    void allowOnly(std::initializer_list<const char*> known) const;
    bool has(const char* key) const { return obj_.contains(key); }

    double number(const char* key, double fallback, double min, double max) const;
    int integer(const char* key, int fallback, int min, int max) const;
    bool boolean(const char* key, bool fallback) const;
    std::string string(const char* key, const std::string& fallback) const;
    std::string oneOf(const char* key, const std::string& fallback,
                      std::initializer_list<const char*> choices) const;
    std::array<double, 3> vec3(const char* key, std::array<double, 3> fallback, double min,
                               double max) const;
    // A nested object (empty object when absent).
    JsonFields child(const char* key) const;
    const nlohmann::json& at(const char* key) const { return obj_.at(key); }
    const nlohmann::json& object() const { return obj_; }
    std::string pathOf(const char* key) const { return path_.empty() ? key : path_ + "." + key; }
    const std::string& file() const { return file_; }

    [[noreturn]] void fail(const std::string& field, const nlohmann::json& value,
                           const std::string& why) const;

private:
    std::string file_;
    const nlohmann::json& obj_;
    std::string path_;
    static const nlohmann::json& emptyObject();
};

}  // namespace engine
