#include "platform/context.hpp"

#include "core/error.hpp"
#include "gl/gl.hpp"
#include "platform/mesa_cache.hpp"

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <optional>

namespace pr {

Backend parse_backend(const std::string& name, const std::string& option)
{
    if (name == "osmesa") return Backend::OSMesa;
    if (name == "egl") return Backend::Egl;
    throw Error(option, "unknown backend '" + name + "' (expected osmesa or egl)");
}

std::string backend_name(Backend backend)
{
    return backend == Backend::OSMesa ? "osmesa" : "egl";
}

std::vector<std::string> available_backends()
{
#ifdef PRISMRELIEF_HAVE_EGL
    return {"osmesa", "egl"};
#else
    return {"osmesa"};
#endif
}

void Context::load_gl(ProcLoader get_proc, const std::string& subject, const std::string& backend)
{
    const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(get_proc));
    if (version == 0) throw Error(subject, "could not load OpenGL entry points");
    const int major = GLAD_VERSION_MAJOR(version);
    const int minor = GLAD_VERSION_MINOR(version);
    if (major < 4 || (major == 4 && minor < 5))
        throw Error(subject, "OpenGL " + std::to_string(major) + "." + std::to_string(minor) +
                                 " context, 4.5 core needed");
    const auto str = [](GLenum name) {
        const auto* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s ? s : "?");
    };
    const std::string gl_version = str(GL_VERSION);
    description_ = backend + ": " + str(GL_RENDERER) + ", OpenGL " + gl_version;
    // Mesa's shader cache turned off where Mesa could not make its folder (platform/mesa_cache.hpp):
    // said once, prefixed, instead of Mesa's own line.
    if (const std::string& why = mesa_shader_cache_off_reason(); !why.empty() && gl_version.find("Mesa") != std::string::npos)
        warn("Mesa's shader cache is off (" + why +
             "): shaders are compiled anew on every run; MESA_SHADER_CACHE_DIR can name a folder for it");
}

namespace {

// The number a variable's value begins with, if it begins with digits ("130", "4.4COMPAT": 4).
std::optional<long> leading_number(const char* value)
{
    if (value == nullptr || !std::isdigit(static_cast<unsigned char>(*value))) return std::nullopt;
    return std::strtol(value, nullptr, 10);
}

} // namespace

std::string mesa_environment_problem(Backend backend)
{
    const std::string name = backend_name(backend);
    const auto set = [](const char* variable) {
        const char* value = std::getenv(variable);
        return value != nullptr && *value ? value : nullptr;
    };
    const char* glsl = set("MESA_GLSL_VERSION_OVERRIDE");
    if (const auto v = leading_number(glsl); v && *v < 450)
        return name + ": MESA_GLSL_VERSION_OVERRIDE=" + glsl + " asks for GLSL under 4.50, which the shaders need " +
               "(Mesa makes no 4.5 context with it; OSMesa crashed under 1.40): unset it";
    if (const char* gl = set("MESA_GL_VERSION_OVERRIDE")) {
        const auto major = leading_number(gl);
        const char* dot = std::strchr(gl, '.');
        const auto minor = dot != nullptr ? leading_number(dot + 1) : std::optional<long>(0);
        if (major && minor && (*major < 4 || (*major == 4 && *minor < 5)))
            return name + ": MESA_GL_VERSION_OVERRIDE=" + gl + " asks for OpenGL under 4.5, which the renderer " +
                   "needs: unset it";
    }
    if (const char* width = set("LP_NATIVE_VECTOR_WIDTH"); width != nullptr) {
        if (const auto v = leading_number(width); v && *v != 128 && *v != 256)
            return name + ": LP_NATIVE_VECTOR_WIDTH=" + width + ": llvmpipe draws at 128 or 256 bits and " +
                   "crashed at others: unset it";
    }
    if (backend == Backend::OSMesa)
        for (const char* variable : {"GALLIUM_TRACE", "GALLIUM_DDEBUG"})
            if (set(variable))
                return name + ": " + variable + " is set: Mesa's OSMesa " +
                       (std::strcmp(variable, "GALLIUM_TRACE") == 0 ? "hung" : "crashed") +
                       " making a context with it: unset it, or draw with the egl backend";
    return {};
}

std::unique_ptr<Context> create_headless_context(Backend backend, const std::string& option)
{
    try {
        // Mesa's own settings that crash or hang it, or refuse a 4.5 context with a word that
        // does not name them (found by an exploratory session, fifty-third).
        if (const std::string problem = mesa_environment_problem(backend); !problem.empty())
            throw Error("--backend", problem);
        return backend == Backend::OSMesa ? create_osmesa_context() : create_egl_context();
    } catch (const Error& e) {
        // The backends name "--backend"; a command whose flag is another says its own.
        if (e.subject() != "--backend" || option == "--backend") throw;
        throw Error(option, e.problem());
    }
}

void preload_backend(Backend backend)
{
    // (Not where Mesa's settings would crash it as it loads: create_headless_context refuses them.)
    if (backend == Backend::OSMesa && mesa_environment_problem(backend).empty()) preload_osmesa();
}

void finish_preload()
{
    finish_osmesa_preload();
}

#ifndef PRISMRELIEF_HAVE_EGL
std::unique_ptr<Context> create_egl_context()
{
    throw Error("--backend", "egl: this build has no EGL support (EGL headers were missing)");
}
#endif

} // namespace pr
