// The dynamic loader's reason for a dlopen that failed (platform/ only: the GL backends).
#pragma once

#include <dlfcn.h>

#include <initializer_list>
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

// The first of `names` that loads (RTLD_NOW | RTLD_LOCAL), or null; `reason` then holds why the
// first one that is there could not be loaded (a library it needs missing; too little address
// space under `ulimit -v`), empty where none is there at all ("not installed").
inline void* open_first_library(std::initializer_list<const char*> names, std::string& reason)
{
    reason.clear();
    for (const char* name : names) {
        if (void* lib = dlopen(name, RTLD_NOW | RTLD_LOCAL)) return lib;
        if (std::string why = loader_reason(name); reason.empty() && why.find("No such file") == std::string::npos)
            reason = std::move(why);
    }
    return nullptr;
}

} // namespace pr
