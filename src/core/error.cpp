#include "core/error.hpp"

#include <cstdio>
#include <mutex>
#include <set>

namespace pr {

void warn(const std::string& message)
{
    static std::mutex mutex;
    static std::set<std::string> said;
    std::lock_guard lock(mutex);
    if (said.insert(message).second) std::fprintf(stderr, "prismrelief: warning: %s\n", message.c_str());
}

} // namespace pr
