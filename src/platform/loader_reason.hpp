// The dynamic loader's reason for a dlopen that just failed (platform/ only: the GL backends).
#pragma once

#include <dlfcn.h>

#include <string>

namespace pr {

// dlerror()'s text for the failed dlopen of `lib`, without the name it starts with ("lib: "):
// "invalid ELF header", "libLLVM-15.so.1: failed to map segment from shared object".
inline std::string loader_reason(const std::string& lib)
{
    const char* e = dlerror();
    std::string why = e ? e : "the dynamic loader gives no reason";
    if (why.rfind(lib + ": ", 0) == 0) why.erase(0, lib.size() + 2);
    return why;
}

} // namespace pr
