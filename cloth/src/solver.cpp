#include "cloth/solver.h"

#include <iterator>

namespace cloth {

const char* toString(StepStatus status) {
    static const char* const names[] = {"ok", "non-finite state", "solver failed"};
    const auto i = std::size_t(status);
    return i < std::size(names) ? names[i] : "?";
}

}  // namespace cloth
