#!/usr/bin/env bash
# Compiles the simulation program (the files StepProgram builds, in its order, after the defines the
# program builder prepends) with clang-14 for a generic SPIR target, in float without cl_khr_fp64 and
# in double, and prints clang's diagnostics: what a strict vendor compiler may reject (docs/opencl.md,
# "Portability"). Needs clang-14 (not a build dependency). Exit status 1 when there is any warning.
#   tools/compile_kernels.sh            both precisions
set -euo pipefail
cd "$(dirname "$0")/.."
files=(spacing_field reduce forces time_step neighbours device_step selftest)
status=0
for precision in float double; do
  src=$(mktemp --suffix=.cl)
  if [ "$precision" = float ]; then
    printf '#define PDMESH_DOUBLE 0\n#define REAL float\n#define REAL2 float2\n#define WG_SIZE 64\n' >"$src"
    ext=-cl_khr_fp64
  else
    printf '#define PDMESH_DOUBLE 1\n#define REAL double\n#define REAL2 double2\n#define WG_SIZE 64\n' >"$src"
    printf '#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n' >>"$src"
    ext=+cl_khr_fp64
  fi
  cat kernels/common.cl >>"$src"
  for f in "${files[@]}"; do printf '\n// ---- %s.cl ----\n' "$f" >>"$src"; cat "kernels/$f.cl" >>"$src"; done
  log=$(clang-14 -x cl -cl-std=CL1.2 -target spir64 -Xclang -finclude-default-header -Xclang "-cl-ext=$ext" \
        -fsyntax-only "$src" 2>&1 || true)
  warnings=$(grep -c "warning:\|error:" <<<"$log" || true)
  echo "$precision ($ext): $warnings warning(s) or error(s)"
  [ -z "$log" ] || echo "$log"
  [ "$warnings" = 0 ] || status=1
  rm -f "$src"
done
exit $status
