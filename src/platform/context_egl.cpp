// EGL backend: headless OpenGL 4.5 core without a window system. Tries, in order, the first
// EGL device (an NVIDIA GPU where present: EGL_EXT_platform_device), Mesa's surfaceless platform
// (llvmpipe or a Mesa GPU driver), then the default display. libEGL is opened at run time, like
// OSMesa, so neither library is linked into the binary and a machine without it gets one line.
#include "platform/context.hpp"
#include "platform/loader_reason.hpp"
#include "platform/mesa_cache.hpp"

#include "core/error.hpp"
#include "core/file_kind.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>

#include <cstdlib>
#include <string>

namespace pr {
namespace {

struct EglApi {
    void* lib = nullptr;
    PFNEGLGETPROCADDRESSPROC get_proc = nullptr;
    template <typename F> F load(const char* name) const { return reinterpret_cast<F>(get_proc(name)); }
};

EglApi& api()
{
    static EglApi a;
    if (!a.lib) {
        // Mesa's libEGL writes its warnings to stderr, unprefixed, before the one line that says
        // why no context came (three to seven lines with GALLIUM_DRIVER=nonexistent; found by an
        // exploratory session, fifty-third): only its fatal ones, where the user set no level.
        setenv("EGL_LOG_LEVEL", "fatal", 0);
        // PRISMRELIEF_EGL_LIBRARY names another libEGL (like PRISMRELIEF_OSMESA_LIBRARY).
        if (const char* lib = std::getenv("PRISMRELIEF_EGL_LIBRARY"); lib && *lib) {
            if (const std::string why = not_a_file_reason(lib); !why.empty())
                throw Error("--backend", std::string("egl: cannot load ") + lib + ": it " + why);
            std::string why;
            a.lib = open_named_library(lib, why);
            if (!a.lib) throw Error("--backend", std::string("egl: cannot load ") + lib + ": " + why);
        }
        std::string reason; // (as OSMesa's: a libEGL there that cannot be loaded says why)
        if (!a.lib) a.lib = open_first_library({"libEGL.so.1", "libEGL.so"}, reason);
        if (!a.lib && !reason.empty()) throw Error("--backend", "egl: libEGL is installed but cannot be loaded: " + reason);
        if (!a.lib) throw Error("--backend", "egl: libEGL is not installed");
        a.get_proc = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(a.lib, "eglGetProcAddress"));
        if (!a.get_proc)
            throw Error("--backend", "egl: " + named_library("PRISMRELIEF_EGL_LIBRARY", "libEGL") +
                                         " has no eglGetProcAddress (not a libEGL)");
    }
    return a;
}

void* egl_get_proc(const char* name)
{
    return reinterpret_cast<void*>(api().get_proc(name));
}

class EglContextImpl final : public Context {
public:
    EglContextImpl()
    {
        const EglApi& a = api();
        auto get_platform_display = a.load<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
        auto query_devices = a.load<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
        auto initialize = a.load<PFNEGLINITIALIZEPROC>("eglInitialize");
        auto get_display = a.load<PFNEGLGETDISPLAYPROC>("eglGetDisplay");
        bind_api_ = a.load<PFNEGLBINDAPIPROC>("eglBindAPI");
        auto choose_config = a.load<PFNEGLCHOOSECONFIGPROC>("eglChooseConfig");
        auto create_context = a.load<PFNEGLCREATECONTEXTPROC>("eglCreateContext");
        auto make_current = a.load<PFNEGLMAKECURRENTPROC>("eglMakeCurrent");
        destroy_context_ = a.load<PFNEGLDESTROYCONTEXTPROC>("eglDestroyContext");
        terminate_ = a.load<PFNEGLTERMINATEPROC>("eglTerminate");
        if (!initialize || !bind_api_ || !choose_config || !create_context || !make_current)
            throw Error("--backend", "egl: libEGL lacks core entry points");

        // Each candidate display is tried all the way to a current context; a display that
        // initializes but offers no OpenGL config (or context) falls through to the next.
        std::string tried;
        const auto attempt = [&](EGLDisplay d, const char* what) {
            std::string why = "no display";
            EGLint major = 0, minor = 0;
            if (d != EGL_NO_DISPLAY && initialize(d, &major, &minor)) {
                display_ = d;
                why = setup(choose_config, create_context, make_current);
                if (why.empty()) {
                    platform_ = what;
                    return true;
                }
                release();
            }
            tried += std::string(tried.empty() ? "" : ", ") + what + ": " + why;
            return false;
        };
        // PRISMRELIEF_EGL_PLATFORM: device (the default) or surfaceless; another value is refused
        // (a misspelt one skipped the device platform without a word).
        const char* prefer = std::getenv("PRISMRELIEF_EGL_PLATFORM");
        const std::string platform = prefer ? prefer : "";
        if (!platform.empty() && platform != "device" && platform != "surfaceless")
            throw Error("--backend", "egl: PRISMRELIEF_EGL_PLATFORM=" + platform + " is not device or surfaceless");
        const bool want_device = platform != "surfaceless";
        bool ok = false;
        if (want_device && get_platform_display && query_devices) {
            EGLDeviceEXT devices[8];
            EGLint count = 0;
            if (query_devices(8, devices, &count))
                for (EGLint i = 0; i < count && !ok; ++i)
                    ok = attempt(get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr), "device");
        }
        if (!ok && get_platform_display)
            ok = attempt(get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                         "surfaceless");
        if (!ok && get_display) ok = attempt(get_display(EGL_DEFAULT_DISPLAY), "default");
        if (!ok) {
            // (A driver the user named is the likely cause: said, as OSMesa's check says it.)
            const char* driver = std::getenv("GALLIUM_DRIVER");
            throw Error("--backend", "egl: no OpenGL 4.5 core context (" + tried + ")" +
                                         (driver != nullptr && *driver
                                              ? std::string("; GALLIUM_DRIVER=") + driver + " is set: unset it (llvmpipe)"
                                              : std::string()));
        }
        try {
            load_gl(&egl_get_proc, "--backend", std::string("EGL (") + platform_ + ")");
        } catch (...) {
            release();
            throw;
        }
    }
    ~EglContextImpl() override { release(); }

private:
    // Config, context and make-current on display_; returns why it failed, or "" on success.
    std::string setup(PFNEGLCHOOSECONFIGPROC choose_config, PFNEGLCREATECONTEXTPROC create_context,
                      PFNEGLMAKECURRENTPROC make_current)
    {
        if (!bind_api_(EGL_OPENGL_API)) return "OpenGL API not supported";
        // EGL_SURFACE_TYPE defaults to EGL_WINDOW_BIT, which headless displays lack.
        const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                         EGL_DONT_CARE, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint n = 0;
        if (!choose_config(display_, config_attribs, &config, 1, &n) || n < 1) return "no OpenGL config";
        const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        ctx_ = create_context(display_, config, EGL_NO_CONTEXT, ctx_attribs);
        if (ctx_ == EGL_NO_CONTEXT) return "no 4.5 core context";
        // Surfaceless: rendering goes to framebuffer objects only (EGL_KHR_surfaceless_context).
        if (!make_current(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_)) return "cannot make current without a surface";
        return "";
    }
    void release()
    {
        if (ctx_ != EGL_NO_CONTEXT && destroy_context_) destroy_context_(display_, ctx_);
        ctx_ = EGL_NO_CONTEXT;
        if (display_ && terminate_) terminate_(display_);
        display_ = nullptr;
    }

    EGLDisplay display_ = nullptr;
    EGLContext ctx_ = EGL_NO_CONTEXT;
    const char* platform_ = "";
    PFNEGLBINDAPIPROC bind_api_ = nullptr;
    PFNEGLDESTROYCONTEXTPROC destroy_context_ = nullptr;
    PFNEGLTERMINATEPROC terminate_ = nullptr;
};

} // namespace

std::unique_ptr<Context> create_egl_context()
{
    prepare_mesa_shader_cache(); // (Mesa's EGL, where it is Mesa's, reads it when the display starts)
    return std::make_unique<EglContextImpl>();
}

} // namespace pr
