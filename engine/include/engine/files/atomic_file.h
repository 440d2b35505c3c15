#pragma once
// Writes a whole file so that readers never see half of it: the text goes to PATH.tmp, is flushed,
// and is renamed over PATH. On failure nothing is left behind and *error names the path and why.

#include <string>

namespace engine {

bool writeFileAtomically(const std::string& path, const std::string& text, std::string* error);

}  // namespace engine
