#!/usr/bin/env bash
# The GPU kit's one command (tools/gpu_kit/build.sh stages it as gpu-kit/run.sh; docs/devices.md,
# "The GPU kit"): on a machine with nothing of ours installed, finds the OpenCL driver, checks the
# device, runs the device tests, the simulation benchmarks and two whole runs, each step under its own
# time budget, and writes OUTDIR/gpu_results.json (rewritten after every step, so a run stopped from
# outside still leaves what it had) and at most 7 logs beside it. Exits 0 whatever the steps did,
# also when no OpenCL GPU is found: the JSON says what was looked for and what was seen.
#
#   run.sh [--local] [--budget SECONDS] [--steps LIST] OUTDIR
#
# --local: PoCL (the CPU) instead of an NVIDIA GPU, with cases small enough for a 2-core machine: the
#   dry run of the same steps. --budget: the whole run's time (default 480 s); each step has its own
#   share and is skipped when too little is left. --steps: a comma-separated subset of driver, bench,
#   tests, whole (default all; the driver search always runs).
# PDMESH_KIT_SEARCH_ROOT=DIR: look for the driver under DIR only (kit_driver.sh; the broken search).
set -uo pipefail

KIT=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=kit_json.sh
source "$KIT/kit_json.sh"
# shellcheck source=kit_driver.sh
source "$KIT/kit_driver.sh"

mode=gpu budget=480 steps=driver,bench,tests,whole out=
while (($#)); do
  case $1 in
    --local) mode=local ;;
    --budget) budget=$2; shift ;;
    --steps) steps=$2; shift ;;
    -h | --help) sed -n '2,16p' "$0"; exit 0 ;;
    -*) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    *) out=$1 ;;
  esac
  shift
done
if [ -z "$out" ] || ! [[ $budget =~ ^[0-9]+$ ]]; then
  echo "usage: run.sh [--local] [--budget SECONDS] [--steps LIST] OUTDIR" >&2
  exit 2
fi
mkdir -p "$out" || exit 2
out=$(cd "$out" && pwd)
wanted() { [[ ",$steps," == *",$1,"* ]]; }

START=$(date +%s)
DEADLINE=$((START + budget))
WORK=$(mktemp -d "${TMPDIR:-/tmp}/pdmesh-gpu-kit.XXXXXX") || exit 2
mkdir -p "$WORK/tmp" "$WORK/pocl-cache"
# The work folder (the whole runs' meshes, gigabytes at 5M nodes) goes at the end;
# PDMESH_KIT_KEEP_WORK=1 keeps it.
if [ -n "${PDMESH_KIT_KEEP_WORK:-}" ]; then
  trap 'rm -f "$out/.gpu_results.json.tmp"' EXIT
else
  trap 'rm -rf "$WORK"; rm -f "$out/.gpu_results.json.tmp"' EXIT
fi
export TMPDIR=$WORK/tmp POCL_CACHE_DIR=${POCL_CACHE_DIR:-$WORK/pocl-cache} PDMESH_TEST_SOURCE_DIR=$KIT
export PATH=$PATH:/usr/local/nvidia/bin:/usr/sbin:/sbin
export HOME=${HOME:-$WORK}
PDMESH=$KIT/bin/pdmesh
CASES=$KIT/cases
# A copy that lost its modes (a transfer that keeps none) still runs.
for f in "$KIT"/bin/pdmesh "$KIT"/bin/test_*; do [ -x "$f" ] || chmod +x "$f" 2>/dev/null; done

# The cases: the GPU's, and the dry run's on a 2-core CPU.
if [ "$mode" = gpu ]; then
  SMALL_ITERATIONS=2000 SMALL_WARMUP=200 LARGE=(1000000 5000000) LARGE_ITERATIONS=200 ANNULUS=annulus_5m
else
  SMALL_ITERATIONS=2000 SMALL_WARMUP=200 LARGE=(100000 500000) LARGE_ITERATIONS=20 ANNULUS=annulus_100k
fi

# ---- results -------------------------------------------------------------------------------------
STEPS_JSON=() BENCH_JSON=() WHOLE_JSON=() TEST_EXES_JSON=()
TESTS_PASSED=0 TESTS_FAILED=0 TESTS_UNFINISHED=() TESTS_NOTE=null
DRIVER_JSON=null SMI_JSON=null KIT_FIT_JSON=null DEVICE_JSON='{"found": null, "reason": "the driver search has not run"}'
COMPLETE=false

kit_info_json() {
  local first=1 key value
  printf '{'
  if [ -f "$KIT/BUILD_INFO" ]; then
    while IFS='=' read -r key value; do
      [ -n "$key" ] || continue
      ((first)) || printf ', '
      first=0
      printf '%s: %s' "$(json_str "$key")" "$(json_str "$value")"
    done <"$KIT/BUILD_INFO"
  fi
  printf '}'
}

machine_json() {
  local cpu glibc mem
  cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null)
  glibc=$(getconf GNU_LIBC_VERSION 2>/dev/null)
  mem=$(awk '/^MemTotal/ { printf "%.0f\n", $2 * 1024; exit }' /proc/meminfo 2>/dev/null)
  printf '{"uname": %s, "cpus": %s, "cpu": %s, "memory_bytes": %s, "glibc": %s, "load_average": %s}' \
    "$(json_str "$(uname -srm)")" "$(json_num "$(nproc 2>/dev/null)")" "$(json_str "$cpu")" "$(json_num "$mem")" \
    "$(json_str "$glibc")" "$(json_str "$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)")"
}

# join_with SEPARATOR ELEMENTS...
join_with() {
  local sep=$1 first=1 a
  shift
  for a in "$@"; do
    ((first)) || printf '%s' "$sep"
    first=0
    printf '%s' "$a"
  done
}

write_results() {
  local now tmp=$out/.gpu_results.json.tmp unfinished
  now=$(date +%s)
  unfinished=$(json_str_array "${TESTS_UNFINISHED[@]}")
  {
    printf '{\n  "format": "pdmesh-gpu-kit-results",\n  "version": 1,\n  "mode": %s,\n  "complete": %s,\n' \
      "$(json_str "$mode")" "$COMPLETE"
    printf '  "started": %s,\n  "wall_s": %s,\n  "budget_s": %s,\n' \
      "$(json_str "$(date -u -d "@$START" +%Y-%m-%dT%H:%M:%SZ 2>/dev/null)")" "$((now - START))" "$budget"
    printf '  "kit": %s,\n  "machine": %s,\n  "kit_fit": %s,\n' "$(kit_info_json)" "$MACHINE_JSON" "$KIT_FIT_JSON"
    printf '  "driver_search": %s,\n  "nvidia_smi": %s,\n  "device": %s,\n' "$DRIVER_JSON" "$SMI_JSON" "$DEVICE_JSON"
    printf '  "tests": {"passed": %s, "failed": %s, "unfinished": %s, "note": %s, "executables": [\n    %s\n  ]},\n' \
      "$TESTS_PASSED" "$TESTS_FAILED" "$unfinished" "$TESTS_NOTE" "$(join_with $',\n    ' "${TEST_EXES_JSON[@]}")"
    printf '  "bench": [\n%s\n  ],\n' "$(join_with $',\n' "${BENCH_JSON[@]}")"
    printf '  "whole_runs": [\n    %s\n  ],\n' "$(join_with $',\n    ' "${WHOLE_JSON[@]}")"
    printf '  "steps": [\n    %s\n  ]\n}\n' "$(join_with $',\n    ' "${STEPS_JSON[@]}")"
  } >"$tmp" && mv -f "$tmp" "$out/gpu_results.json"
}

# run_step NAME BUDGET LOG COMMAND...: runs COMMAND under `timeout` with the smaller of BUDGET and
# what is left of the whole budget, its output appended to OUTDIR/LOG; records the step. Returns the
# command's status (124 when stopped at the time limit, 125 when skipped for want of time).
STEP_STATUS=
run_step() {
  local name=$1 want=$2 log=$3
  shift 3
  local left allowed t0 t1 rc
  left=$((DEADLINE - $(date +%s) - 5))
  allowed=$((want < left ? want : left))
  if ((allowed < 10)); then
    STEP_STATUS=skipped
    STEPS_JSON+=("$(printf '{"name": %s, "status": "skipped", "note": "out of time: %s s of the budget left", "budget_s": %s}' \
      "$(json_str "$name")" "$left" "$want")")
    echo "run.sh: $name skipped: ${left} s left" >&2
    return 125
  fi
  echo "run.sh: $name (at most $allowed s) -> $log" >&2
  printf '== %s: %s\n' "$name" "$*" >>"$out/$log"
  t0=$(date +%s.%N)
  timeout -k 10 "$allowed" "$@" >>"$out/$log" 2>&1
  rc=$?
  t1=$(date +%s.%N)
  case $rc in
    0) STEP_STATUS=ok ;;
    124 | 137) STEP_STATUS=timeout ;;
    *) STEP_STATUS=failed ;;
  esac
  local seconds
  seconds=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
  printf '== %s: %s (exit status %s) after %s s of %s\n' "$name" "$STEP_STATUS" "$rc" "$seconds" "$allowed" >>"$out/$log"
  STEPS_JSON+=("$(printf '{"name": %s, "status": "%s", "exit_status": %s, "seconds": %s, "budget_s": %s, "log": %s, "tail": %s}' \
    "$(json_str "$name")" "$STEP_STATUS" "$rc" "$seconds" "$allowed" "$(json_str "$log")" \
    "$( [ "$STEP_STATUS" = ok ] && printf null || json_str "$(tail -n 15 "$out/$log")")")")
  echo "run.sh: $name: $STEP_STATUS after $seconds s" >&2
  return "$rc"
}

skip_step() {
  STEPS_JSON+=("$(printf '{"name": %s, "status": "skipped", "note": %s}' "$(json_str "$1")" "$(json_str "$2")")")
}

MACHINE_JSON=$(machine_json)
write_results
echo "run.sh: mode $mode, budget $budget s, results in $out/gpu_results.json, work in $WORK" >&2

# ---- driver: search, nvidia-smi, pdmesh devices --check -------------------------------------------
source "$KIT/kit_steps.sh"
step_driver
write_results
if [ "$DEVICE_FOUND" != true ]; then
  for s in bench tests whole; do wanted "$s" && skip_step "$s" "no OpenCL device: $DEVICE_REASON"; done
else
  wanted bench && step_bench
  wanted tests && step_tests
  wanted whole && step_whole
fi
COMPLETE=true
write_results
echo "run.sh: done in $(($(date +%s) - START)) s: $out/gpu_results.json" >&2
exit 0
