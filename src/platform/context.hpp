#pragma once
// An OpenGL 4.5 core context behind one small interface. Backends are sibling files
// (context_osmesa.cpp, context_egl.cpp, and the viewer's GLFW window); only they include
// osmesa.h / EGL / GLFW headers. Each loads the GL entry points through its own
// GetProcAddress into glad, so libGL is never linked next to libOSMesa (contract: linked
// together, nothing draws).
#include <memory>
#include <string>
#include <vector>

namespace pr {

enum class Backend { OSMesa, Egl };

// "osmesa" | "egl"; throws pr::Error(option, …): the flag the user typed (conemap's is
// --gl-backend, its --backend being cpu|gpu).
Backend parse_backend(const std::string& name, const std::string& option = "--backend");
std::string backend_name(Backend backend);
std::vector<std::string> available_backends(); // compiled in (EGL needs headers at build time)

class Context {
public:
    virtual ~Context() = default;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    // "OSMesa: llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6"
    const std::string& description() const { return description_; }

protected:
    Context() = default;
    // Loads GL entry points through `get_proc` into glad, checks for 4.5 core and fills the
    // description. Throws pr::Error(subject, …) when GL is too old or loading fails.
    using ProcLoader = void* (*)(const char* name);
    void load_gl(ProcLoader get_proc, const std::string& subject, const std::string& backend);

private:
    std::string description_;
};

// Creates a headless context and makes it current. All rendering goes to framebuffer objects,
// so the context's own surface is tiny. Throws pr::Error(option, …) when the backend's
// library is missing or no 4.5 core context can be created.
std::unique_ptr<Context> create_headless_context(Backend backend, const std::string& option = "--backend");

// What in the environment keeps Mesa from giving the backend a working 4.5 context (empty: nothing
// known): MESA_GLSL_VERSION_OVERRIDE under 450 and MESA_GL_VERSION_OVERRIDE under 4.5,
// LP_NATIVE_VECTOR_WIDTH other than 128 or 256, and for OSMesa GALLIUM_TRACE (it hung) and
// GALLIUM_DDEBUG (it crashed). create_headless_context() refuses them, naming the variable.
std::string mesa_environment_problem(Backend backend);

// Starts loading the backend's library on a thread of its own, so that a command can read its
// mesh and maps meanwhile; create_headless_context() then waits for it. Loading libOSMesa (Mesa
// and LLVM) takes about 75 ms on the 2-core machine, most of what a context costs. Errors are
// reported by create_headless_context(), not here. No-op for EGL.
void preload_backend(Backend backend);
// Waits until a preload has finished (if one was started). The process must not exit while the
// library loads: main() calls it before returning.
void finish_preload();

// Backend factories (defined in their own files).
std::unique_ptr<Context> create_osmesa_context();
void preload_osmesa();
void finish_osmesa_preload();
std::unique_ptr<Context> create_egl_context(); // throws when built without EGL headers

} // namespace pr
