#pragma once
// Load-time errors: one message that names the file, the field and the value.

#include <stdexcept>
#include <string>

namespace engine {

class ConfigError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace engine
