#pragma once
// Mesa's shader cache and a folder it cannot make. Mesa makes its cache folder when a context is
// created (MESA_SHADER_CACHE_DIR, else $XDG_CACHE_HOME, else the user's home/.cache; each with
// mesa_shader_cache inside) and, where a folder of that chain cannot be made or is not a folder,
// prints its own unprefixed line ("Failed to create /x for shader cache (Permission denied)
// ---disabling.") on every run. The backends ask first: where Mesa would fail, its cache is turned
// off (MESA_SHADER_CACHE_DISABLE) before Mesa reads its environment, and a Mesa context says why
// in one warning of ours instead.
#include <functional>
#include <string>

namespace pr {

// Why Mesa could not make its shader cache folder, "" where it could (or the cache is off, or
// Mesa would skip it without a word). `env` reads a variable (null where unset); `home` is the
// user's home folder from the password database (Mesa's last place, which ignores $HOME). A
// folder missing from the chain is made and removed again to learn whether it can be.
std::string mesa_shader_cache_problem(const std::function<const char*(const char*)>& env, const std::string& home);

// Once per process, before a backend loads Mesa (no other thread may read the environment
// meanwhile): unsets an empty MESA_SHADER_CACHE_DIR (or MESA_GLSL_CACHE_DIR), and turns Mesa's
// cache off where mesa_shader_cache_problem() then finds a problem.
void prepare_mesa_shader_cache();

// The problem found by prepare_mesa_shader_cache(), "" where none (Context::load_gl warns with
// it on a Mesa context).
const std::string& mesa_shader_cache_off_reason();

} // namespace pr
