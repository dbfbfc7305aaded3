// The dynamic loader's reason for a dlopen that failed (platform/ only: the GL backends).
#pragma once

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
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

// The library a variable names (PRISMRELIEF_OSMESA_LIBRARY, PRISMRELIEF_EGL_LIBRARY), opened; or
// null, and in `why` the loader's reason. A name without a folder is looked for where the loader
// looks for libraries, not here: where that fails and the working folder has a file so named, the
// reason says how to name it ("./NAME"; it said "No such file or directory" alone; found by an
// exploratory session, fifty-third).
inline void* open_named_library(const char* lib, std::string& why)
{
    void* handle = dlopen(lib, RTLD_NOW | RTLD_LOCAL);
    if (handle) return handle;
    why = loader_reason(lib);
    const std::string name = lib;
    if (name.find('/') == std::string::npos && access(lib, F_OK) == 0)
        why += " (a name without a folder is looked for in the library path: ./" + name + " names the file here)";
    return nullptr;
}

// What the messages call the library: the file a variable names, else the system's.
inline std::string named_library(const char* variable, const char* system)
{
    const char* lib = std::getenv(variable);
    return lib != nullptr && *lib ? lib : system;
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
