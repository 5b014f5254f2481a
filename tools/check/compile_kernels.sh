#!/usr/bin/env bash
# Compiles the simulation program exactly as the host builds it (build/kernel_source prints it: the
# program builder's defines, common.cl and StepProgram's files in order), followed by selftest.cl and
# pair_floor.cl (programs of their own, built with the same common defines), with
# clang-14 for a generic SPIR target, in float without cl_khr_fp64 and in double, with each force loop
# (vector, scalar), and prints clang's diagnostics: what a strict vendor compiler may reject
# (docs/opencl.md, "Portability"). Needs clang-14 (not a build dependency) and the kernel_source target.
# Exit status 1 when there is any warning.
#   tools/check/compile_kernels.sh [BUILD_DIR]      (default: build)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
if [ ! -x "$build/kernel_source" ]; then
  echo "compile_kernels: $build/kernel_source is missing: cmake --build $build --target kernel_source" >&2
  exit 1
fi
status=0
for precision in float double; do
  for loop in vector scalar; do
    src=$(mktemp --suffix=.cl)
    "$build/kernel_source" "$precision" "$loop" >"$src"
    for extra in selftest.cl pair_floor.cl; do
      printf '\n// ---- %s ----\n' "$extra" >>"$src"
      cat "kernels/$extra" >>"$src"
    done
    if [ "$precision" = float ]; then ext=-cl_khr_fp64; else ext=+cl_khr_fp64; fi
    log=$(clang-14 -x cl -cl-std=CL1.2 -target spir64 -Xclang -finclude-default-header -Xclang "-cl-ext=$ext" \
          -fsyntax-only "$src" 2>&1 || true)
    warnings=$(grep -c "warning:\|error:" <<<"$log" || true)
    echo "$precision ($ext), $loop force loop: $warnings warning(s) or error(s)"
    [ -z "$log" ] || echo "$log"
    [ "$warnings" = 0 ] || status=1
    rm -f "$src"
  done
done
exit $status
