// OSMesa backend: Mesa's off-screen renderer (llvmpipe), OpenGL 4.5 core.
// libOSMesa is opened at run time (dlopen), so a machine without it gets one clear error
// instead of a loader failure, and the binary never links a second `gl*` provider.
#include "platform/context.hpp"

#include "core/error.hpp"
#include "core/file_kind.hpp"
#include "platform/loader_reason.hpp"
#include "platform/mesa_cache.hpp"

#include <GL/osmesa.h>
#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <future>
#include <mutex>
#include <string>
#include <system_error>
#include <vector>

namespace pr {
namespace {

struct OSMesaApi {
    void* lib = nullptr;
    OSMesaContext (*create_attribs)(const int*, OSMesaContext) = nullptr;
    GLboolean (*make_current)(OSMesaContext, void*, GLenum, GLsizei, GLsizei) = nullptr;
    void (*destroy)(OSMesaContext) = nullptr;
    OSMESAproc (*get_proc)(const char*) = nullptr;
    std::string error; // why it could not be loaded (then nothing above is set)
};

// Opens libOSMesa and looks up its entry points; never throws (the error is kept for api()).
// Loading it is most of the cost of a context (Mesa and LLVM: about 75 ms on the 2-core machine).
OSMesaApi load_osmesa()
{
    OSMesaApi a;
    // PRISMRELIEF_OSMESA_LIBRARY names another build of libOSMesa (a newer Mesa, say).
    if (const char* lib = std::getenv("PRISMRELIEF_OSMESA_LIBRARY"); lib && *lib) {
        // (dlopen would wait forever on a FIFO without a writer.)
        if (const std::string why = not_a_file_reason(lib); !why.empty())
            return {.error = std::string("osmesa: cannot load ") + lib + ": it " + why};
        std::string why;
        a.lib = open_named_library(lib, why);
        if (!a.lib) return {.error = std::string("osmesa: cannot load ") + lib + ": " + why};
    }
    // Where a name is there but cannot be loaded (a library it needs is missing; too little
    // address space under `ulimit -v`: LLVM's segments do not map), the loader's reason is said
    // instead of "not installed" (found by an exploratory session, forty-eighth).
    std::string reason;
    if (!a.lib) a.lib = open_first_library({"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}, reason);
    if (!a.lib && !reason.empty()) return {.error = "osmesa: libOSMesa is installed but cannot be loaded: " + reason};
    if (!a.lib) return {.error = "osmesa: libOSMesa is not installed (run scripts/setup.sh)"};
    a.create_attribs = reinterpret_cast<decltype(a.create_attribs)>(dlsym(a.lib, "OSMesaCreateContextAttribs"));
    a.make_current = reinterpret_cast<decltype(a.make_current)>(dlsym(a.lib, "OSMesaMakeCurrent"));
    a.destroy = reinterpret_cast<decltype(a.destroy)>(dlsym(a.lib, "OSMesaDestroyContext"));
    a.get_proc = reinterpret_cast<decltype(a.get_proc)>(dlsym(a.lib, "OSMesaGetProcAddress"));
    if (!a.create_attribs || !a.make_current || !a.destroy || !a.get_proc)
        return {.error = "osmesa: " + named_library("PRISMRELIEF_OSMESA_LIBRARY", "libOSMesa") +
                         " lacks OSMesaCreateContextAttribs (not a libOSMesa, or one older than Mesa 11)"};
    return a;
}

// The library is loaded once per process, on a thread of its own when preload_backend() asked
// for it early (the caller reads its mesh and height map meanwhile), else on first use.
std::shared_future<OSMesaApi>& loading()
{
    static std::shared_future<OSMesaApi> f;
    return f;
}

std::mutex& loading_mutex()
{
    static std::mutex m;
    return m;
}

void start_loading(std::launch how)
{
    const std::lock_guard<std::mutex> lock(loading_mutex());
    if (loading().valid()) return;
    prepare_mesa_shader_cache(); // (before Mesa's thread: it may set a variable)
    loading() = std::async(how, load_osmesa).share();
}

const OSMesaApi& api()
{
    start_loading(std::launch::deferred); // runs here, unless a preload already runs or ran
    const OSMesaApi& a = loading().get();
    if (!a.error.empty()) throw Error("--backend", a.error);
    return a;
}

void* osmesa_get_proc(const char* name)
{
    return reinterpret_cast<void*>(api().get_proc(name));
}

class OSMesaContextImpl final : public Context {
public:
    OSMesaContextImpl()
    {
        // OSMesa draws with Mesa's software rasterizers; named any other driver, Mesa 22's
        // OSMesaCreateContextAttribs crashes (SIGSEGV: swr, zink, d3d12, virpipe, swrast, a
        // misspelling). softpipe has no OpenGL 4.5 and fails cleanly below.
        const char* driver = std::getenv("GALLIUM_DRIVER");
        if (driver != nullptr && *driver && std::strcmp(driver, "llvmpipe") != 0 &&
            std::strcmp(driver, "softpipe") != 0)
            throw Error("--backend", std::string("osmesa: GALLIUM_DRIVER=") + driver +
                                         " is not a driver OSMesa draws with (llvmpipe; Mesa crashes with others): "
                                         "unset it, or draw with the egl backend");
        const OSMesaApi& a = api();
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                               OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                               OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        ctx_ = a.create_attribs(attribs, nullptr);
        if (!ctx_ && driver != nullptr && std::strcmp(driver, "softpipe") == 0)
            throw Error("--backend", "osmesa: GALLIUM_DRIVER=softpipe has no OpenGL 4.5 core context: unset it "
                                     "(llvmpipe), or draw with the egl backend");
        if (!ctx_) throw Error("--backend", "osmesa: could not create an OpenGL 4.5 core context");
        // The context's own surface is never drawn to (rendering goes to FBOs): keep it tiny.
        buffer_.assign(16 * 16 * 4, 0);
        if (!a.make_current(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, 16, 16)) {
            a.destroy(ctx_);
            throw Error("--backend", "osmesa: could not make the context current");
        }
        try {
            load_gl(&osmesa_get_proc, "--backend", "OSMesa");
        } catch (...) {
            a.destroy(ctx_);
            throw;
        }
    }
    ~OSMesaContextImpl() override { api().destroy(ctx_); }

private:
    OSMesaContext ctx_ = nullptr;
    std::vector<unsigned char> buffer_;
};

} // namespace

std::unique_ptr<Context> create_osmesa_context()
{
    return std::make_unique<OSMesaContextImpl>();
}

void preload_osmesa()
{
    try {
        start_loading(std::launch::async);
    } catch (const std::system_error&) {
        // No thread to spare: the library loads on first use instead.
    }
}

void finish_osmesa_preload()
{
    const std::lock_guard<std::mutex> lock(loading_mutex());
    if (loading().valid()) loading().wait(); // (a deferred load has run: api() made it to get it)
}

} // namespace pr
