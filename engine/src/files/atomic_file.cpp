#include "engine/files/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace engine {

bool writeFileAtomically(const std::string& path, const std::string& text, std::string* error) {
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) {
        if (error) *error = path + ": cannot write: " + std::strerror(errno);
        return false;
    }
    const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    const int writeErrno = errno;
    const bool closed = std::fclose(f) == 0;
    if (!written || !closed) {
        if (error) *error = path + ": cannot write: " + std::strerror(written ? errno : writeErrno) + " (disk full?)";
        std::remove(tmp.c_str());
        return false;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        if (error) *error = path + ": cannot rename into place: " + std::strerror(errno);
        std::remove(tmp.c_str());
        return false;
    }
    return true;
}

}  // namespace engine
