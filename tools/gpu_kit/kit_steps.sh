# The steps of the GPU kit's run.sh (sourced by it, after its variables and run_step): the driver and
# device check, the benchmarks, the device tests and the whole runs. Each fills its part of the
# results (DEVICE_JSON, BENCH_JSON, TEST_*, WHOLE_JSON) from the logs and calls write_results.

# Step budgets in seconds: the GPU's, then the dry run's on 2 CPU cores (PoCL).
if [ "$mode" = gpu ]; then
  BUDGET_CHECK=90 BUDGET_BENCH_SMALL=60 BUDGET_BENCH_LARGE=(50 100) BUDGET_TESTS=150 BUDGET_WHOLE_SMALL=40 BUDGET_WHOLE_LARGE=280
else
  BUDGET_CHECK=90 BUDGET_BENCH_SMALL=90 BUDGET_BENCH_LARGE=(40 80) BUDGET_TESTS=150 BUDGET_WHOLE_SMALL=60 BUDGET_WHOLE_LARGE=150
fi

# Sets KITBIN, the folder the binaries run from: KIT/bin, or, where the machine's glibc is older than
# some bundled libraries need (GLIBC_NEEDS, from build.sh; e.g. Debian 12's libstdc++ needs 2.36 and
# Ubuntu 22.04 has 2.35), a copy of it without those, so that the machine's own libraries of the same
# soname are used. Sets KIT_FIT_JSON. PDMESH_KIT_GLIBC stands for the machine's version (the kit's test).
fit_glibc() {
  local log=$1 have f v
  KITBIN=$KIT/bin
  have=${PDMESH_KIT_GLIBC:-$(getconf GNU_LIBC_VERSION 2>/dev/null | awk '{ print $2 }')}
  local -a left_out=()
  if [ -n "$have" ] && [ -f "$KIT/GLIBC_NEEDS" ]; then
    while read -r f v; do
      [[ $f == lib* && -n $v ]] || continue
      [ "$(printf '%s\n%s\n' "$v" "$have" | sort -V | tail -n 1)" = "$have" ] || left_out+=("$f")
    done <"$KIT/GLIBC_NEEDS"
  fi
  if ((${#left_out[@]})); then
    mkdir -p "$WORK/bin"
    cp -a "$KIT/bin/." "$WORK/bin/"
    for f in "${left_out[@]}"; do rm -f "$WORK/bin/$f"; done
    KITBIN=$WORK/bin
    echo "== glibc $have is older than ${left_out[*]} need: the kit runs from $KITBIN without them (the machine's own are used)" >>"$out/$log"
  fi
  PDMESH=$KITBIN/pdmesh
  # RUNPATH ($ORIGIN) comes after LD_LIBRARY_PATH: an image's LD_LIBRARY_PATH (CUDA images set one), or
  # the driver's folder the search appends, must not put the machine's libraries before the kit's.
  export LD_LIBRARY_PATH=$KITBIN${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  KIT_FIT_JSON=$(printf '{"machine_glibc": %s, "kit_glibc_min": %s, "libraries_left_out": %s, "bin": %s}' \
    "$(json_str "$have")" "$(json_str "$(sed -n 's/^glibc_min=//p' "$KIT/BUILD_INFO" 2>/dev/null)")" \
    "$(json_str_array "${left_out[@]}")" "$(json_str "$KITBIN")")
}

# The driver search, nvidia-smi, and `pdmesh devices --check`: sets DEVICE_FOUND (true or false),
# DEVICE_REASON and DEVICE_JSON.
step_driver() {
  local log=driver.log
  fit_glibc "$log"
  driver_search "$mode" "$WORK" "$out/$log"
  nvidia_smi_facts "$out/$log"
  DEVICE_FOUND=false
  DEVICE_REASON=
  local start_error=null
  if ! run_step "pdmesh --version" 20 "$log" "$PDMESH" --version; then
    start_error=$(json_str "$(tail -n 5 "$out/$log")")
    DEVICE_REASON="the kit's pdmesh does not start on this machine (see start_error; the kit needs glibc $(sed -n 's/^glibc_min=//p' "$KIT/BUILD_INFO" 2>/dev/null) or newer)"
  else
    { echo "== ldd $PDMESH"; ldd "$PDMESH" 2>&1; } >>"$out/$log"
    run_step "pdmesh devices --check" "$BUDGET_CHECK" "$log" "$PDMESH" devices --check
  fi
  # What `pdmesh devices --check` printed: the device lines, the pick, each device's check.
  local -a listed=() check_lines=()
  local line pick= check= spec= type= description= bit=null
  while IFS= read -r line; do
    case $line in
      "  opencl:"*) listed+=("${line#  }") ;;
      "--device auto picks: "*) pick=${line#--device auto picks: } ;;
    esac
  done <"$out/$log"
  # The device type that counts: a GPU, or on --local any; PDMESH_KIT_WANT_TYPE (e.g. CPU) for the
  # kit's test, which runs the GPU mode's search on PoCL under NVIDIA's library name.
  local want_type=GPU
  [ "$mode" = local ] && want_type=
  want_type=${PDMESH_KIT_WANT_TYPE-$want_type}
  for line in "${listed[@]}"; do
    local s t
    read -r s t _ <<<"$line"
    if [ -z "$want_type" ] || [ "$t" = "$want_type" ]; then
      spec=$s type=$t description=$(sed -E 's/^[^ ]+ +[^ ]+ +//' <<<"$line")
      break
    fi
  done
  if [ -n "$spec" ]; then
    check=$(sed -n "s/^check $spec: //p" "$out/$log" | tail -n 1)
    mapfile -t check_lines < <(awk -v h="check $spec: " 'index($0, h) == 1 { on = 1; next } on && /^  / { sub(/^  /, ""); print; next } { on = 0 }' "$out/$log")
    if grep -q "^  step: .*bit for bit" <<<"$(printf '  %s\n' "${check_lines[@]}")"; then bit=true
    elif ((${#check_lines[@]})); then bit=false; fi
    DEVICE_FOUND=true
  elif [ -z "$DEVICE_REASON" ]; then
    local what="OpenCL GPU"
    [ "$mode" = local ] && what="OpenCL device"
    if [ -z "$DRIVER_LIB" ]; then
      local given=
      [ -n "${DRIVER_VENDORS_GIVEN:-}" ] && given="; OCL_ICD_VENDORS was given as $DRIVER_VENDORS_GIVEN, holding $(ls "$DRIVER_VENDORS_GIVEN" 2>/dev/null | grep -c '\.icd$') .icd files"
      DEVICE_REASON="no $what: no driver library ($(sed -n 's/^looking for \(.*\) in: .*/\1/p' "$out/$log" | head -n 1)) in the folders searched and none registered in an .icd file$given; the kit's ICD loader listed ${#listed[@]} devices"
    else
      DEVICE_REASON="no $what: the driver library $DRIVER_LIB was found and registered, but the ICD loader listed ${#listed[@]} device(s)${listed:+: ${listed[*]}}"
    fi
  fi
  DEVICE_JSON=$(printf '{"found": %s, "reason": %s, "spec": %s, "type": %s, "description": %s, "auto_picks": %s, "listed": %s, "check": %s, "check_lines": %s, "bit_identical_double": %s, "start_error": %s}' \
    "$DEVICE_FOUND" "$( [ -n "$DEVICE_REASON" ] && json_str "$DEVICE_REASON" || printf null)" \
    "$( [ -n "$spec" ] && json_str "$spec" || printf null)" "$( [ -n "$type" ] && json_str "$type" || printf null)" \
    "$( [ -n "$description" ] && json_str "$description" || printf null)" "$( [ -n "$pick" ] && json_str "$pick" || printf null)" \
    "$(json_str_array "${listed[@]}")" "$( [ -n "$check" ] && json_str "$check" || printf null)" \
    "$(json_str_array "${check_lines[@]}")" "$bit" "$start_error")
  [ "$DEVICE_FOUND" = true ] || echo "run.sh: $DEVICE_REASON" >&2
}

# bench_case LOG BUDGET ARGS...: one `pdmesh bench` run; its rows (those it printed before a time-out
# too) go into BENCH_JSON.
bench_case() {
  local log=$1 want=$2
  shift 2
  run_step "bench ${log%.log}" "$want" "$log" "$PDMESH" bench --cases-dir "$CASES" "$@"
  local rows
  rows=$(bench_rows_json "$out/$log")
  [ -n "$rows" ] && BENCH_JSON+=("$rows")
  write_results
}

step_bench() {
  bench_case bench_30p30n.log "$BUDGET_BENCH_SMALL" --cases 30p30n --iterations "$SMALL_ITERATIONS" --warmup "$SMALL_WARMUP"
  local k n
  for k in 0 1; do
    n=${LARGE[$k]}
    bench_case "bench_graded_$((n / 1000))k.log" "${BUDGET_BENCH_LARGE[$k]}" --cases graded_1m --large-nodes "$n" \
      --large-iterations "$LARGE_ITERATIONS" --large-warmup 20 --skip-host-large
  done
}

# The dry run's tests: on 2 CPU cores the whole set takes many minutes (CI runs it), so --local runs
# the quick executables whole and a few test cases of the long ones (Catch2 test specs; "" = all),
# enough to show that every kind runs from the kit, finds its cases and is counted.
declare -A LOCAL_TESTS=(
  [test_opencl_infra]="" [test_opencl_canary]="" [test_device_row_offsets]="" [test_device_boundary]=""
  [test_device_clearance]="" [test_device_floor]=""
  [test_device_cases]="the bit-identity list names every case in cases/,device run: square200 is bit-identical to the host over 200 iterations from both starts"
  [test_device_simulation]="device run: 10 iterations agree with the host node by node (double),device run in float stays close to the host for 10 iterations"
)

# The device test executables (bin/test_*), as many at once as the machine has cores, each stopped at
# the step's end; their outputs one after the other in tests.log.
step_tests() {
  local log=tests.log dir=$WORK/tests jobs t0 step_end
  mkdir -p "$dir"
  jobs=$(nproc 2>/dev/null || echo 2)
  t0=$(date +%s.%N)
  local left=$((DEADLINE - $(date +%s) - 5))
  local allowed=$((BUDGET_TESTS < left ? BUDGET_TESTS : left))
  if ((allowed < 10)); then
    skip_step tests "out of time: $left s of the budget left"
    TESTS_NOTE=$(json_str "not run: out of time")
    return
  fi
  step_end=$(($(date +%s) + allowed))
  echo "run.sh: tests ($jobs at a time, at most $allowed s) -> $log" >&2
  local -a exes=()
  local exe name running=0
  for exe in "$KITBIN"/test_*; do
    [ -x "$exe" ] || continue
    [ "$mode" = gpu ] || [ -n "${LOCAL_TESTS[$(basename "$exe")]+set}" ] && exes+=("$exe")
  done
  [ "$mode" = gpu ] || TESTS_NOTE=$(json_str "--local: ${#exes[@]} executables, the long ones limited to a few test cases (kit_steps.sh, LOCAL_TESTS)")
  for exe in "${exes[@]}"; do
    while ((running >= jobs)); do
      wait -n 2>/dev/null
      running=$((running - 1))
    done
    name=$(basename "$exe")
    local limit=$((step_end - $(date +%s)))
    if ((limit < 5)); then
      echo "not started: the tests' $allowed s were used up" >"$dir/$name.log"
      echo 125 >"$dir/$name.rc"
      continue
    fi
    local -a spec=()
    [ "$mode" = gpu ] || [ -z "${LOCAL_TESTS[$name]}" ] || spec=("${LOCAL_TESTS[$name]}")
    (
      s=$(date +%s.%N)
      timeout -k 5 "$limit" "$exe" "${spec[@]}" >"$dir/$name.log" 2>&1
      echo $? >"$dir/$name.rc"
      awk -v a="$s" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f\n", b - a }' >"$dir/$name.seconds"
    ) &
    running=$((running + 1))
  done
  wait
  : >"$out/$log"
  local rc counts passed failed status
  for exe in "${exes[@]}"; do
    name=$(basename "$exe")
    rc=$(cat "$dir/$name.rc" 2>/dev/null || echo 125)
    counts=$(catch_counts "$dir/$name.log")
    { echo "== $name (exit status $rc)"; cat "$dir/$name.log"; } >>"$out/$log"
    if [ -n "$counts" ]; then
      read -r passed failed <<<"$counts"
    else
      passed=0 failed=1
      TESTS_UNFINISHED+=("$name")
    fi
    case $rc in
      0) status=ok ;;
      124 | 137) status=timeout ;;
      125) status=not_started ;;
      *) [ -n "$counts" ] && status=failed || status=crashed ;;
    esac
    TESTS_PASSED=$((TESTS_PASSED + passed))
    TESTS_FAILED=$((TESTS_FAILED + failed))
    TEST_EXES_JSON+=("$(printf '{"name": %s, "status": "%s", "exit_status": %s, "passed": %s, "failed": %s, "seconds": %s, "failed_cases": %s}' \
      "$(json_str "$name")" "$status" "$rc" "$passed" "$failed" "$(json_num "$(cat "$dir/$name.seconds" 2>/dev/null)")" \
      "$(catch_failed_names "$dir/$name.log")")")
  done
  local seconds
  seconds=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  STEPS_JSON+=("$(printf '{"name": "tests", "status": "%s", "seconds": %s, "budget_s": %s, "log": "%s", "note": %s}' \
    "$( ((TESTS_FAILED == 0)) && echo ok || echo failed)" "$seconds" "$allowed" "$log" \
    "$(json_str "${#exes[@]} executables, $jobs at a time: $TESTS_PASSED test cases passed, $TESTS_FAILED failed, ${#TESTS_UNFINISHED[@]} executables without a summary")")")
  echo "run.sh: tests: $TESTS_PASSED passed, $TESTS_FAILED failed after $seconds s" >&2
  write_results
}

# whole_case NAME LOG BUDGET: one `pdmesh mesh` run of case NAME on the device, as
# `pdmesh bench --whole-run` times it (pictures included), its timings file into WHOLE_JSON: the
# phase sums, and the whole file as "timings" (the simulation's split: device steps, builds, the
# stopping rule's measurements, population events), with each kernel's launches and device seconds
# (PDMESH_KERNEL_PROFILE) as "kernels".
whole_case() {
  local name=$1 log=$2 want=$3
  local kernels=$WORK/whole/${name//[^A-Za-z0-9_]/_}.kernels.tsv
  mkdir -p "$WORK/whole"
  run_step "whole $name" "$want" "$log" env PDMESH_KERNEL_PROFILE="$kernels" "$PDMESH" bench --whole-run --cases "$name" \
    --cases-dir "$CASES" --repeat 1 --backends opencl --work-dir "$WORK/whole"
  local status=$STEP_STATUS timings=$WORK/whole/${name}_opencl/run1/timings.json
  if [ -f "$timings" ]; then
    WHOLE_JSON+=("$(printf '{"case": %s, "status": "%s", "wall_s": %s, "wall_in_process_s": %s, "cpu_s": %s, "peak_rss_bytes": %s, "nodes": %s, "triangles": %s, "iterations": %s, "converged": %s, "simulation_s": %s, "backend": %s, "phases": %s, "timings": %s, "kernels": %s}' \
      "$(json_str "$name")" "$status" "$(json_num "$(whole_run_wall "$name" "$out/$log")")" \
      "$(json_num "$(timings_value wall "$timings")")" "$(json_num "$(timings_value cpu "$timings")")" \
      "$(json_num "$(timings_value peak_rss_bytes "$timings")")" "$(json_num "$(timings_value nodes "$timings")")" \
      "$(json_num "$(timings_value triangles "$timings")")" "$(json_num "$(timings_value iterations "$timings")")" \
      "$(json_num "$(timings_value converged "$timings")")" "$(json_num "$(timings_value simulation_seconds "$timings")")" \
      "$(json_str "$(timings_value backend "$timings")")" "$(timings_phases_json "$timings")" "$(cat "$timings")" \
      "$(kernel_profile_json "$kernels")")")
  elif [ "$status" = skipped ]; then
    WHOLE_JSON+=("$(printf '{"case": %s, "status": "skipped", "wall_s": null, "phases": {}, "note": "out of time"}' "$(json_str "$name")")")
  else
    WHOLE_JSON+=("$(printf '{"case": %s, "status": "%s", "wall_s": null, "phases": {}, "note": "no timings file: the run did not finish (see %s)"}' \
      "$(json_str "$name")" "$status" "$log")")
  fi
  write_results
}

step_whole() {
  whole_case 30p30n:geometry whole_30p30n.log "$BUDGET_WHOLE_SMALL"
  whole_case "$ANNULUS" "whole_${ANNULUS}.log" "$BUDGET_WHOLE_LARGE"
}
