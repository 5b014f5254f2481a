#!/usr/bin/env bash
# Measures how long `pdmesh mesh` takes to stop after a SIGINT in each phase of a large run (a
# measuring script, not a test; docs/robustness.md "Stopped by Ctrl-C" has its table).
#
# Usage: tools/bench/interrupt_latency.sh PDMESH [NODES] [WORKDIR] [EXTRA ARGS...]
#   PDMESH   the binary (build/pdmesh)
#   NODES    about how many nodes: a unit square at a uniform spacing giving that many (default 1000000)
#   WORKDIR  scratch folder (default /tmp/pdmesh_latency)
#   EXTRA    more `pdmesh mesh` options (default: --device host)
#
# First one whole run with --timings gives every phase's wall time; then, for each phase, a run that
# sends itself SIGINT half way through that phase (PDMESH_TEST_SIGNAL_IN_PHASE=NAME@SECONDS; at its
# start for phases under 0.1 s) and records the time from the signal to the process's end, the exit
# status and what the stop left in the output folder. Prints a Markdown table.
set -euo pipefail
bin=$(readlink -f "$1")
nodes=${2:-1000000}
work=${3:-/tmp/pdmesh_latency}
shift $(( $# < 3 ? $# : 3 ))
extra=("$@")
[ ${#extra[@]} -gt 0 ] || extra=(--device host)
mkdir -p "$work"
# A unit square (four curves) and the uniform spacing h whose hexagonal packing, 2 / (sqrt(3) h^2)
# nodes per unit area, gives about NODES.
printf '2\n0 0\n1 0\n2\n1 0\n1 1\n2\n1 1\n0 1\n2\n0 1\n0 0\n' > "$work/square.crv"
h=$(python3 -c "import math; print(repr(math.sqrt(2 / (math.sqrt(3) * $nodes))))")
args=(mesh "$work/square.crv" --set spacing.field=expression --set "spacing.expression=$h" --set boundary.nodes=spacing
      --iterations 3 --stop iterations --formats msh,vtu,png --max-nodes 100000000 "${extra[@]}")

rm -rf "$work/whole"
echo "reference run: ${args[*]} --out $work/whole" >&2
"$bin" "${args[@]}" --out "$work/whole" -q --timings "$work/timings.json" > /dev/null
# name<TAB>wall for each phase that is not a background picture, in order.
python3 - "$work/timings.json" > "$work/phases.tsv" <<'EOF'
import json, sys
t = json.load(open(sys.argv[1]))
print("# nodes", int(t.get("nodes", 0)), "triangles", int(t.get("triangles", 0)), file=sys.stderr)
seen = set()
for p in t["phases"]:
    if p["background"] or p["name"] in seen:
        continue
    seen.add(p["name"])
    print(f"{p['name']}\t{p['wall']:.3f}")
EOF

echo "| phase | phase wall (s) | signal at (s into it) | stop latency (s) | exit | left in --out |"
echo "|---|---|---|---|---|---|"
while IFS=$'\t' read -r name wall; do
  delay=$(python3 -c "w = $wall; print(f'{w / 2:.3f}' if w >= 0.1 else '0')")
  out="$work/stop"
  rm -rf "$out"
  log="$work/stop.log"
  set +e
  PDMESH_TEST_SIGNAL_IN_PHASE="$name@$delay" "$bin" "${args[@]}" --out "$out" -q > /dev/null 2> "$log"
  status=$?
  end=$(date +%s.%N)
  set -e
  sent=$(sed -n 's/^pdmesh: test: SIGINT sent at //p' "$log" | head -1)
  if [ -z "$sent" ]; then
    latency="(phase ended before the signal)"
  else
    latency=$(python3 -c "print(f'{$end - $sent:.3f}')")
  fi
  left=$( [ -d "$out" ] && ls -A "$out" | tr '\n' ' ' || echo "(no folder)")
  echo "| $name | $wall | $delay | $latency | $status | $left |"
done < "$work/phases.tsv"
