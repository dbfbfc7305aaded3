// OSMesa backend: Mesa's off-screen renderer (llvmpipe), OpenGL 4.5 core.
// libOSMesa is opened at run time (dlopen), so a machine without it gets one clear error
// instead of a loader failure, and the binary never links a second `gl*` provider.
#include "platform/context.hpp"

#include "core/error.hpp"

#include <GL/osmesa.h>
#include <dlfcn.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace pr {
namespace {

struct OSMesaApi {
    void* lib = nullptr;
    OSMesaContext (*create_attribs)(const int*, OSMesaContext) = nullptr;
    GLboolean (*make_current)(OSMesaContext, void*, GLenum, GLsizei, GLsizei) = nullptr;
    void (*destroy)(OSMesaContext) = nullptr;
    OSMESAproc (*get_proc)(const char*) = nullptr;
};

OSMesaApi& api()
{
    static OSMesaApi a;
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
        OSMesaApi& a = api();
        if (!a.lib) {
            // PRISMRELIEF_OSMESA_LIBRARY names another build of libOSMesa (a newer Mesa, say).
            if (const char* lib = std::getenv("PRISMRELIEF_OSMESA_LIBRARY"); lib && *lib) {
                a.lib = dlopen(lib, RTLD_NOW | RTLD_LOCAL);
                if (!a.lib) throw Error("--backend", std::string("osmesa: cannot load ") + lib);
            }
            for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}) {
                if (a.lib) break;
                a.lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
            }
            if (!a.lib) throw Error("--backend", "osmesa: libOSMesa is not installed (run scripts/setup.sh)");
            a.create_attribs = reinterpret_cast<decltype(a.create_attribs)>(dlsym(a.lib, "OSMesaCreateContextAttribs"));
            a.make_current = reinterpret_cast<decltype(a.make_current)>(dlsym(a.lib, "OSMesaMakeCurrent"));
            a.destroy = reinterpret_cast<decltype(a.destroy)>(dlsym(a.lib, "OSMesaDestroyContext"));
            a.get_proc = reinterpret_cast<decltype(a.get_proc)>(dlsym(a.lib, "OSMesaGetProcAddress"));
            if (!a.create_attribs || !a.make_current || !a.destroy || !a.get_proc) {
                a.lib = nullptr;
                throw Error("--backend", "osmesa: libOSMesa lacks OSMesaCreateContextAttribs (Mesa too old)");
            }
        }
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                               OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                               OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        ctx_ = a.create_attribs(attribs, nullptr);
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

} // namespace pr
