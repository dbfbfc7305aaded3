#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (Debug, build-asan/).
# LeakSanitizer suppresses only leaks inside Mesa's own libraries (tests/lsan.supp). The preset also
# sets use_tls=0: LSan's tracer crashes (SEGV, "Tracer caught signal 11") reading the thread-local
# storage of llvmpipe's worker threads at exit on some runs; without TLS as roots LSan can only
# report more, never hide one of ours; what it then reports of glibc's dynamic loader (reachable
# only through TLS) is suppressed by its module (ld-linux) in tests/lsan.supp. The window tests preload
# Mesa's GLX and DRI libraries so that their leaks stay attributable (and suppressed) after
# libglvnd unloads them (tests/cli/view_run.cmake).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake --preset asan >/dev/null
cmake --build --preset asan --parallel "$(nproc)"
ctest --preset asan --parallel "$(nproc)" "$@"
