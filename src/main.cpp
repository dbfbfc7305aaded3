#include "app/cli.hpp"
#include "core/atomic_file.hpp"
#include "platform/context.hpp"

#include <cstdlib>
#ifdef __GLIBC__
#include <malloc.h>
#endif

int main(int argc, char** argv)
{
#ifdef __GLIBC__
    // glibc gives the free memory at its heap's top back to the system once more than 128 KiB
    // lies there (less where it adjusts), and llvmpipe's draws free and take again many small
    // blocks: each draw of a large scene touched them afresh, which costs on a virtual machine
    // (`render --technique reference` of the torus, 1.8 M triangles at 256²: the draw 240-1070 ms
    // from run to run, 140-160 ms with 256 MiB kept; docs/benchmarks.md, forty-ninth session).
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
    // An empty or relative XDG_CACHE_HOME is ignored (the XDG specification; the cone-map cache
    // does): Mesa, reading the same variable for its shader cache, printed "Failed to create  for
    // shader cache (No such file or directory)---disabling." on every run.
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && xdg[0] != '/') unsetenv("XDG_CACHE_HOME");
    // Ctrl-C, kill, a closed terminal: the outputs and cache entries being written are removed.
    pr::remove_temporaries_on_signals();
    const int status = pr::run_cli(argc, argv);
    // A command that failed before it made its context may have left Mesa loading on another
    // thread (preload_backend): exiting under it would run the destructors that the library's
    // static constructors are registering (LLVM's, found by AddressSanitizer). Wait for it first.
    pr::finish_preload();
    return status;
}
