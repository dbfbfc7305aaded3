#include "app/cli.hpp"
#include "core/atomic_file.hpp"
#include "platform/context.hpp"

int main(int argc, char** argv)
{
    // Ctrl-C, kill, a closed terminal: the outputs and cache entries being written are removed.
    pr::remove_temporaries_on_signals();
    const int status = pr::run_cli(argc, argv);
    // A command that failed before it made its context may have left Mesa loading on another
    // thread (preload_backend): exiting under it would run the destructors that the library's
    // static constructors are registering (LLVM's, found by AddressSanitizer). Wait for it first.
    pr::finish_preload();
    return status;
}
