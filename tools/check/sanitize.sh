#!/usr/bin/env bash
# Builds pdmesh with AddressSanitizer + UndefinedBehaviorSanitizer in build-asan/ and runs the
# whole test suite there: tools/check/sanitize.sh [extra ctest arguments]. Exit status: ctest's.
# Leak reports from inside PoCL/LLVM and fontconfig (process-lifetime caches) are suppressed by
# tests/lsan.supp; see docs/robustness.md for what was found and why.
set -euo pipefail
cd "$(dirname "$0")/../.."

build=build-asan
# PDMESH_SANITIZE adds float-cast-overflow too: GCC leaves it out of -fsanitize=undefined, and
# readers cast parsed doubles to integers.
# -O1 -g1: the optimisation AddressSanitizer's documentation recommends, and line tables, all a
# report's stack needs; -O2 -g compiles the instrumented code several times slower. The tools under
# tools/ are not built: no test runs them.
cmake -S . -B "$build" -DPDMESH_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPDMESH_BUILD_TOOLS=OFF \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" \
  ${PDMESH_CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)"

# halt_on_error: the first report fails the test; UB already aborts (-fno-sanitize-recover).
# use_sigaltstack=0 and use_tls=0 work around two faults of GCC 12's sanitizer runtime with the LLVM
# inside PoCL (docs/robustness.md, "OpenCL (PoCL) under the sanitizers"): a thread that set PoCL up
# exits with LLVM's alternate signal stack, which ASan then tries to unmap as its own; and
# LeakSanitizer's tracer crashes on a stale dynamic-TLS entry a dlclose'd kernel library leaves.
# Neither hides a report: ASan's own stack-overflow handling loses the alternate stack only, and
# without TLS roots LeakSanitizer can report more leaks, not fewer.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:use_sigaltstack=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/lsan.supp:print_suppressions=0:use_tls=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

ctest --test-dir "$build" --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
