#!/usr/bin/env bash
# The GPU kit's quick checks (ctest gpu_kit_*), without building the kit or its long dry run: a kit
# folder is made of the scripts in tools/gpu_kit, the build's pdmesh and cases/, then
#   parsers        the JSON helpers on known inputs (a bench row, Catch2 summaries, a timings file);
#   broken_search  run.sh with the driver search pointed at an empty root and an empty OCL_ICD_VENDORS:
#                  exit 0, no device, the facts and the skipped steps in a well-formed JSON;
#   unregistered_driver  the GPU mode's search finds a driver library no .icd file names (PoCL under
#                  NVIDIA's name) and registers it itself; without a GPU among the devices, says so;
#   local_driver   run.sh --local --steps driver: finds PoCL, checks it, reports it in the JSON.
#   tools/gpu_kit/test_kit.sh CHECK PDMESH SOURCE_DIR
set -euo pipefail
check=$1 pdmesh=$2 src=$3
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/gpu_kit_test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
kit=$tmp/kit
mkdir -p "$kit/bin"
cp "$here"/run.sh "$here"/kit_*.sh "$kit/"
ln -s "$pdmesh" "$kit/bin/pdmesh"
ln -s "$src/cases" "$kit/cases"
printf 'commit=test\nglibc_min=2.0\n' >"$kit/BUILD_INFO"
fail() {
  echo "test_kit: $check: $*" >&2
  for log in "$tmp"/out*/driver.log; do [ -f "$log" ] && { echo "--- $log (last 40 lines)" >&2; tail -n 40 "$log" >&2; }; done
  exit 1
}
expect_eq() { [ "$1" = "$2" ] || fail "$3: got '$1', expected '$2'"; }
# What run.sh keeps of the test's environment under env -i: PoCL's kernel cache, and the sanitizer
# options of tools/check/sanitize.sh, without which a sanitized pdmesh fails inside PoCL's LLVM
# (docs/robustness.md, "OpenCL (PoCL) under the sanitizers").
kept_env=()
for name in POCL_CACHE_DIR ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS; do
  [ -n "${!name:-}" ] && kept_env+=("$name=${!name}")
done

case $check in
  parsers)
    # shellcheck source=kit_json.sh
    source "$here/kit_json.sh"
    expect_eq "$(json_str $'a"b\\c\nd\te')" '"a\"b\\c\nd\te"' "json_str"
    expect_eq "$(json_num 1.5e-3) $(json_num 12) $(json_num -) $(json_num 1.2.3)" "1.5e-3 12 null null" "json_num"
    expect_eq "$(json_str_array x 'y z')" '["x", "y z"]' "json_str_array"
    cat >"$tmp/bench.log" <<'EOF'
| case | backend | nodes | iterations | ms/iteration | node-iterations/s | pair interactions/s | ns per node-iteration | pairs examined per pair | device split, ms/iteration | bytes/iteration | commands | rebuild | peak | host/device time |
|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|
| 30p30n | host reference | 14412 | 2000 | 3.912 | 3.68e+06 | 9.9e+07 | 271 | 1.45 | - | - | - | - | 812 / - | - |
| 30p30n | opencl:0:0 CPU (double, vector loop) | 14412 | 2000 | 1.527 | 9.44e+06 | 2.5e+08 | 106 | 2.10 (rebuilds 1.2) | bin 0.01 / gather 0.2 | 35 | 2.00 / 0.01 / 0.00 / 0.00 / 0.01 (1 it.) | 9 | 900 / 770 | 2.56 |
EOF
    rows=$(bench_rows_json "$tmp/bench.log")
    expect_eq "$(grep -c '"case": "30p30n"' <<<"$rows")" 2 "bench rows"
    grep -q '"backend": "opencl:0:0 CPU (double, vector loop)", "nodes": 14412, "iterations": 2000, "ms_per_iteration": 1.527' <<<"$rows" ||
      fail "bench row fields: $rows"
    grep -q '"host_over_device": 2.56}' <<<"$rows" || fail "bench ratio: $rows"
    # With the floor: the host row against the CPU's floor, the device row against the device's.
    cat >"$tmp/bench_floor.log" <<'EOF'
| case | backend | nodes | iterations | ms/iteration | node-iterations/s | pair interactions/s | ns per node-iteration | pairs examined per pair | device split, ms/iteration | bytes/iteration | commands | rebuild | peak | host/device time | floor | x floor |
|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|
| 30p30n | host reference | 11093 | 20 | 10.229 | 1.08e+06 | 8.49e+06 | 922 | 2.67 | - | - | - | - | 23996 / - | - | 0.268 / 0.251 | 40.71 |
| 30p30n | opencl:0:0 GPU (double, scalar loop) | 11093 | 20 | 0.165 | 2.65e+06 | 2.08e+07 | 377 | 2.82 | bin 0.00 | 49631 | 2.00 | 17.00 | 23996 / 705 | 2.45 | device 0.031 | 5.32 |
EOF
    rows=$(bench_rows_json "$tmp/bench_floor.log")
    grep -q '"host_over_device": null, "floor_ms_scalar_vector": "0.268 / 0.251", "device_floor_ms": null, "over_floor": 40.71}' <<<"$rows" ||
      fail "bench host floor: $rows"
    grep -q '"host_over_device": 2.45, "floor_ms_scalar_vector": null, "device_floor_ms": 0.031, "over_floor": 5.32}' <<<"$rows" ||
      fail "bench device floor: $rows"
    printf '%s\n' "====" "All tests passed (1234 assertions in 12 test cases)" >"$tmp/pass.log"
    expect_eq "$(catch_counts "$tmp/pass.log")" "12 0" "Catch2 all passed"
    dashes=-------------------------------------------------------------------------------
    printf '%s\n' "$dashes" "device run: a case" "  a section" "$dashes" "/x.cpp:10" "......" "" "/x.cpp:12: FAILED:" \
      "  CHECK( a == b )" "====" "test cases:  5 |  4 passed | 1 failed" "assertions: 9 | 8 passed | 1 failed" >"$tmp/fail.log"
    expect_eq "$(catch_counts "$tmp/fail.log")" "4 1" "Catch2 with a failure"
    expect_eq "$(catch_failed_names "$tmp/fail.log")" '["device run: a case a section"]' "failed test names"
    printf 'Segmentation fault\n' >"$tmp/crash.log"
    expect_eq "$(catch_counts "$tmp/crash.log")" "" "Catch2 without a summary"
    cat >"$tmp/timings.json" <<'EOF'
{
  "format": "pdmesh-timings",
  "wall": 6.431629,
  "nodes": 12164,
  "backend": "opencl:0:0 (GPU, double)",
  "phases": [
    {"name": "read", "wall": 0.030131, "cpu": 0.027506, "background": false},
    {"name": "simulation", "wall": 5.1, "cpu": 5.0, "background": false},
    {"name": "mesh.png", "wall": 0.5, "cpu": 0.5, "background": true},
    {"name": "read", "wall": 0.01, "cpu": 0.01, "background": false}
  ]
}
EOF
    expect_eq "$(timings_phases_json "$tmp/timings.json")" \
      '{"read": 0.040131, "simulation": 5.100000}, "pictures_background_s": 0.500000' "timings phases"
    expect_eq "$(timings_value wall "$tmp/timings.json") $(timings_value backend "$tmp/timings.json")" \
      "6.431629 opencl:0:0 (GPU, double)" "timings values"
    printf '%s\n' "| case | backend | nodes | triangles | iterations | wall s | CPU | RSS | load |" \
      "| annulus_5m | opencl | 5000000 | 9900000 | 650 (converged) | 58.1 / 58.2 / 58.3 | 90.0 | 5000 | 1.0 / 2.0 |" >"$tmp/whole.log"
    expect_eq "$(whole_run_wall annulus_5m "$tmp/whole.log")" 58.2 "whole-run wall"
    ;;
  broken_search)
    mkdir -p "$tmp/empty-root" "$tmp/empty-vendors"
    # And a machine glibc older than one (made-up) bundled library needs: left out of the copy run.
    printf 'pdmesh 2.30\nlibnewer.so.1 2.99\nlibolder.so.1 2.2.5\n' >"$kit/GLIBC_NEEDS"
    touch "$kit/bin/libnewer.so.1" "$kit/bin/libolder.so.1"
    status=0
    env -i PATH=/usr/bin:/bin HOME="$tmp" "${kept_env[@]}" PDMESH_KIT_SEARCH_ROOT="$tmp/empty-root" OCL_ICD_VENDORS="$tmp/empty-vendors" \
      PDMESH_KIT_GLIBC=2.35 "$kit/run.sh" --budget 120 "$tmp/out" || status=$?
    expect_eq "$status" 0 "run.sh's exit status without a driver"
    python3 "$here/check_results.py" --expect-no-device "$tmp/out/gpu_results.json" || fail "gpu_results.json"
    grep -q '"reason": "no OpenCL GPU: no driver library' "$tmp/out/gpu_results.json" || fail "the reason is not the missing driver"
    grep -q "libnvidia-opencl.so\*" "$tmp/out/gpu_results.json" || fail "the JSON does not say what was looked for"
    grep -q "OpenCL devices (0)" "$tmp/out/driver.log" || fail "driver.log lacks what the ICD loader listed"
    grep -q '"machine_glibc": "2.35", "kit_glibc_min": "2.0", "libraries_left_out": \["libnewer.so.1"\]' \
      "$tmp/out/gpu_results.json" || fail "the library needing a newer glibc was not left out"
    files=$(ls "$tmp/out" | wc -l)
    ((files <= 8)) || fail "$files files in OUTDIR"
    ;;
  unregistered_driver)
    # The GPU mode's search on a root whose driver library is not registered in any .icd file, as in a
    # container whose image has no /etc/OpenCL/vendors/nvidia.icd: PoCL stands in for NVIDIA's library.
    # awk reads the whole list: an early exit would end ldconfig with SIGPIPE, which pipefail and set -e
    # turn into a silent exit of this script.
    pocl=$( { ldconfig -p 2>/dev/null || /sbin/ldconfig -p; } | awk '$1 == "libpocl.so.2" && !found { print $NF; found = 1 }')
    [ -n "$pocl" ] || fail "PoCL (libpocl.so.2) is not installed"
    mkdir -p "$tmp/root/usr/local/nvidia/lib64" "$tmp/root/etc/OpenCL/vendors"
    ln -s "$pocl" "$tmp/root/usr/local/nvidia/lib64/libnvidia-opencl.so.1"
    # PoCL finds its device modules (pocl/ beside it) and headers (../../share/pocl) from the path it
    # was loaded by.
    ln -s "$(dirname "$(readlink -f "$pocl")")/pocl" "$tmp/root/usr/local/nvidia/lib64/pocl"
    mkdir -p "$tmp/root/usr/local/share"
    ln -s /usr/share/pocl "$tmp/root/usr/local/share/pocl"
    status=0
    env -i PATH=/usr/bin:/bin HOME="$tmp" "${kept_env[@]}" \
      PDMESH_KIT_SEARCH_ROOT="$tmp/root" PDMESH_KIT_WANT_TYPE=CPU "$kit/run.sh" --steps driver --budget 120 "$tmp/out" || status=$?
    expect_eq "$status" 0 "run.sh's exit status"
    python3 "$here/check_results.py" --expect-device --steps driver "$tmp/out/gpu_results.json" || fail "gpu_results.json"
    grep -q "\"chosen\": \"$tmp/root/usr/local/nvidia/lib64/libnvidia-opencl.so.1\", \"how\": \"not registered by the image: the kit registered it\"" \
      "$tmp/out/gpu_results.json" || fail "the unregistered library was not chosen and registered"
    # And without the stand-in type, the same machine has no GPU: said so, exit 0.
    env -i PATH=/usr/bin:/bin HOME="$tmp" "${kept_env[@]}" \
      PDMESH_KIT_SEARCH_ROOT="$tmp/root" "$kit/run.sh" --steps driver --budget 120 "$tmp/out2" || fail "exit status"
    grep -q '"reason": "no OpenCL GPU: the driver library .* was found and registered, but the ICD loader listed 1 device' \
      "$tmp/out2/gpu_results.json" || fail "a CPU-only machine is not reported as having no GPU"
    ;;
  local_driver)
    status=0
    env -i PATH=/usr/bin:/bin HOME="$tmp" "${kept_env[@]}" "$kit/run.sh" --local --steps driver --budget 120 "$tmp/out" || status=$?
    expect_eq "$status" 0 "run.sh's exit status"
    python3 "$here/check_results.py" --expect-device --steps driver "$tmp/out/gpu_results.json" || fail "gpu_results.json"
    grep -q '"bit_identical_double": true' "$tmp/out/gpu_results.json" || fail "the check does not report bit-identity"
    grep -q '"chosen": ".*libpocl' "$tmp/out/gpu_results.json" || fail "the search did not choose PoCL"
    ;;
  *) fail "unknown check" ;;
esac
echo "test_kit: $check: ok"
