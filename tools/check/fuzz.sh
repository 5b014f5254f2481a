#!/usr/bin/env bash
# Fuzzes every reader: tools/check/fuzz.sh [SECONDS] [TARGET...] (default 60 s each, all targets).
# Configures a clang build with -DPDMESH_FUZZ=ON in build-fuzz/, runs the targets one at a time
# and prints executions and findings per target. Findings (crash-*, leak-*, timeout-*, oom-*)
# land in build-fuzz/findings/TARGET/; the growing corpus in build-fuzz/corpus/TARGET/ (the
# committed seeds in tests/fuzz/corpus/TARGET/ are only read). See docs/robustness.md.
set -euo pipefail
cd "$(dirname "$0")/../.."

seconds=${1:-60}
shift || true
build=build-fuzz
max_len=${FUZZ_MAX_LEN:-8192}   # bytes; the largest seed is well below
max_findings=${FUZZ_MAX_FINDINGS:-5}  # per target: after a finding the fuzzer restarts for the time left
# The memory budget of one execution: an input of at most max_len bytes must not need more. Above
# either limit libFuzzer stops with an oom-* finding (-malloc_limit_mb: any single allocation larger;
# -rss_limit_mb: the whole process).
rss_limit_mb=${FUZZ_RSS_LIMIT_MB:-1024}
malloc_limit_mb=${FUZZ_MALLOC_LIMIT_MB:-256}

if ! command -v clang++ >/dev/null; then
  echo "fuzz: clang++ not found (Debian: apt-get install clang libclang-rt-dev)" >&2
  exit 2
fi
# FUZZ_BUILD=0 runs the targets as built (e.g. several fuzz.sh at once, each on its own targets).
if [ "${FUZZ_BUILD:-1}" != 0 ]; then
  cmake -S . -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DPDMESH_FUZZ=ON -DPDMESH_BUILD_TESTS=OFF >/dev/null
  cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" --target fuzz_all
fi

targets=("$@")
if ((${#targets[@]} == 0)); then
  for src in tests/fuzz/fuzz_*.cpp; do targets+=("$(basename "$src" .cpp)"); done
fi

# The entries write each input to a scratch file: on tmpfs that is ~40x faster than on disk.
if [ -z "${TMPDIR:-}" ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
# Leaks are findings too; UBSan reports abort (-fno-sanitize-recover) and print a stack.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

summary=()
total_findings=0
for t in "${targets[@]}"; do
  bin="$build/fuzz/$t"
  [ -x "$bin" ] || { echo "fuzz: no target $t" >&2; exit 2; }
  work="$build/corpus/$t" findings="$build/findings/$t" log="$build/logs/$t.log"
  mkdir -p "$work" "$findings" "$(dirname "$log")"
  : >"$log"
  before=$(find "$findings" -type f | wc -l)
  execs=0 left=$seconds runs=0
  while ((left > 0 && runs <= max_findings)); do
    start=$(date +%s)
    set +e
    "$bin" -max_total_time="$left" -timeout=10 -rss_limit_mb="$rss_limit_mb" -malloc_limit_mb="$malloc_limit_mb" \
           -max_len="$max_len" -print_final_stats=1 \
           -artifact_prefix="$findings/" "$work" "tests/fuzz/corpus/$t" >>"$log" 2>&1
    rc=$?
    set -e
    # The last "#N" status line of this run is its execution count.
    n=$(grep -aoE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
    execs=$((execs + ${n:-0}))
    echo "--- run ended, exit status $rc" >>"$log"
    left=$((left - ($(date +%s) - start)))
    ((rc == 0)) && break
    runs=$((runs + 1))
  done
  found=$(( $(find "$findings" -type f | wc -l) - before ))
  total_findings=$((total_findings + found))
  summary+=("$(printf '%-28s %12s executions  %3d new findings  (%s)' "$t" "$execs" "$found" "$log")")
done

echo
echo "fuzz: ${seconds}s per target, at most ${malloc_limit_mb} MB per allocation and ${rss_limit_mb} MB in all"
printf '%s\n' "${summary[@]}"
if ((total_findings > 0)); then
  echo "fuzz: findings in $build/findings/ — reproduce with: $build/fuzz/TARGET FILE; keep each as tests/fuzz/regressions/TARGET/NAME"
  exit 1
fi
