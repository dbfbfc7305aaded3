#include "platform/context.hpp"

#include "core/error.hpp"
#include "gl/gl.hpp"
#include "platform/mesa_cache.hpp"

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

std::unique_ptr<Context> create_headless_context(Backend backend, const std::string& option)
{
    try {
        return backend == Backend::OSMesa ? create_osmesa_context() : create_egl_context();
    } catch (const Error& e) {
        // The backends name "--backend"; a command whose flag is another says its own.
        if (e.subject() != "--backend" || option == "--backend") throw;
        throw Error(option, e.problem());
    }
}

void preload_backend(Backend backend)
{
    if (backend == Backend::OSMesa) preload_osmesa();
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
