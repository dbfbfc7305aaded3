#include "platform/mesa_cache.hpp"

#include "core/file_kind.hpp"

#include <pwd.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

namespace pr {
namespace {

bool is_folder(const std::string& path)
{
    struct stat st {};
    return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// Mesa's step for one folder of its chain (util/disk_cache_os.c, mkdir_if_needed): a folder
// there is used, anything else there fails, and a missing one is made. Here a missing one is
// made and removed again; `made` says so, as what follows in the chain is then made inside it.
std::string folder_problem(const std::string& path, bool& made)
{
    struct stat st {};
    if (stat(path.c_str(), &st) == 0) return S_ISDIR(st.st_mode) ? "" : path + " is not a folder";
    if (mkdir(path.c_str(), 0700) == 0) {
        rmdir(path.c_str());
        made = true;
        return "";
    }
    const int error = errno;
    if (error == EEXIST && is_folder(path)) return ""; // (made meanwhile)
    // (A link to nothing read "cannot make …/dl: File exists"; found by an exploratory session.)
    if (const std::string link = broken_link_reason(path); !link.empty()) return path + " " + link;
    return "cannot make " + path + ": " + std::strerror(error);
}

// True where Mesa reads a value as true (util/u_debug.c, debug_get_bool_option): 1, y, yes, t,
// true in any case; anything else leaves its default, the cache on.
bool mesa_true(const char* value)
{
    if (value == nullptr) return false;
    for (const char* word : {"1", "y", "yes", "t", "true"})
        if (strcasecmp(value, word) == 0) return true;
    return false;
}

std::string& off_reason()
{
    static std::string reason;
    return reason;
}

std::string home_folder()
{
    long size = sysconf(_SC_GETPW_R_SIZE_MAX);
    std::vector<char> buffer(std::size_t(size > 0 ? size : 16384));
    struct passwd entry {};
    struct passwd* found = nullptr;
    while (getpwuid_r(getuid(), &entry, buffer.data(), buffer.size(), &found) == ERANGE && buffer.size() < (1u << 20))
        buffer.resize(buffer.size() * 2);
    return found && found->pw_dir ? std::string(found->pw_dir) : std::string();
}

} // namespace

std::string mesa_shader_cache_problem(const std::function<const char*(const char*)>& env, const std::string& home)
{
    // Off already (either name; Mesa says the old one is deprecated on its own), or a process
    // whose user is not the real user (Mesa then has no cache at all).
    if (env("MESA_SHADER_CACHE_DISABLE")) {
        if (mesa_true(env("MESA_SHADER_CACHE_DISABLE"))) return "";
    } else if (mesa_true(env("MESA_GLSL_CACHE_DISABLE"))) {
        return "";
    }
    if (getuid() != geteuid() || getgid() != getegid()) return "";
    // The chain of folders Mesa makes, in order (disk_cache_generate_cache_dir). Where a folder
    // the chain goes into is missing and not made by it, Mesa stops without a word.
    std::vector<std::string> chain;
    const char* dir = env("MESA_SHADER_CACHE_DIR");
    if (dir == nullptr || *dir == '\0') dir = env("MESA_GLSL_CACHE_DIR");
    const char* xdg = env("XDG_CACHE_HOME");
    if (dir != nullptr && *dir != '\0') {
        chain = {dir, std::string(dir) + "/mesa_shader_cache"};
    } else if (xdg != nullptr && *xdg != '\0') {
        chain = {xdg, std::string(xdg) + "/mesa_shader_cache"};
    } else {
        if (home.empty() || !is_folder(home)) return "";
        chain = {home + "/.cache", home + "/.cache/mesa_shader_cache"};
    }
    for (const std::string& folder : chain) {
        bool made = false;
        if (std::string why = folder_problem(folder, made); !why.empty()) return why;
        if (made) break; // (what follows would go into a folder made now)
    }
    return "";
}

void prepare_mesa_shader_cache()
{
    static std::once_flag once;
    std::call_once(once, [] {
        // An empty folder variable is taken as unset (as main() does with XDG_CACHE_HOME): Mesa
        // tried to make "" and said "Failed to create  for shader cache".
        for (const char* name : {"MESA_SHADER_CACHE_DIR", "MESA_GLSL_CACHE_DIR"})
            if (const char* value = std::getenv(name); value != nullptr && *value == '\0') unsetenv(name);
        const std::string why = mesa_shader_cache_problem([](const char* name) { return std::getenv(name); },
                                                          home_folder());
        if (why.empty()) return;
        off_reason() = why;
        setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);
    });
}

const std::string& mesa_shader_cache_off_reason()
{
    return off_reason();
}

} // namespace pr
