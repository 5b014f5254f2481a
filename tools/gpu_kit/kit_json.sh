# JSON helpers of the GPU kit's run.sh (sourced, not run): quoting, numbers, and the parsers that turn
# what pdmesh prints (the bench table, Catch2's summary, the timings file, `pdmesh devices`) into JSON
# fragments. Plain bash and POSIX awk only: the GPU machine has nothing of ours installed (no jq, and no
# python3 that the kit may count on).

# A JSON string of $1: backslash, quote and control characters escaped.
json_str() {
  local s=$1
  s=${s//\\/\\\\}
  s=${s//\"/\\\"}
  s=${s//$'\t'/\\t}
  s=${s//$'\n'/\\n}
  s=${s//$'\r'/\\r}
  s=$(printf '%s' "$s" | tr -d '\000-\010\013\014\016-\037')
  printf '"%s"' "$s"
}

# $1 as a JSON number, or null when it is not one.
json_num() {
  if [[ $1 =~ ^-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?$ ]]; then
    printf '%s' "$1"
  else
    printf 'null'
  fi
}

# A JSON array of strings: one element per argument.
json_str_array() {
  local first=1 a
  printf '['
  for a in "$@"; do
    ((first)) || printf ', '
    first=0
    json_str "$a"
  done
  printf ']'
}

# The last N lines of a file as one JSON string (what a failed step said), or null without the file.
json_tail() {
  if [ -f "$2" ]; then json_str "$(tail -n "$1" "$2")"; else printf 'null'; fi
}

# The rows of a `pdmesh bench` table (printed to the log as they finish), one JSON object per row,
# joined by ",\n". Columns: case | backend | nodes | iterations | ms/iteration | node-iterations/s |
# pair interactions/s | ns per node-iteration | pairs examined | device split | bytes/iteration |
# commands per iteration | per rebuild | host RSS / device bytes per node | host/device time, and in
# tables with the pair-force floor: floor ms/iteration | x floor. The floor cell of a host row is the
# host CPU's "scalar / vector" (floor_ms_scalar_vector), of a device row "device T", the device's own
# floor (device_floor_ms); x floor is the row's time over its own floor.
bench_rows_json() {
  awk -F'|' '
    function q(s) { gsub(/^ +| +$/, "", s); gsub(/\\/, "\\\\", s); gsub(/"/, "\\\"", s); return "\"" s "\"" }
    function n(s) { gsub(/^ +| +$/, "", s); return s ~ /^-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?$/ ? s : "null" }
    /^\| / && NF >= 17 {
      nodes = $4; gsub(/ /, "", nodes)
      if (nodes !~ /^[0-9]+$/) next
      if (count++) printf ",\n"
      printf "    {\"case\": %s, \"backend\": %s, \"nodes\": %s, \"iterations\": %s, \"ms_per_iteration\": %s, ", \
             q($2), q($3), n($4), n($5), n($6)
      printf "\"ns_per_node_iteration\": %s, \"pairs_examined_per_pair\": %s, \"device_split_ms\": %s, ", \
             n($9), q($10), q($11)
      printf "\"bytes_per_iteration\": %s, \"commands_per_iteration\": %s, \"commands_per_rebuild\": %s, ", \
             n($12), q($13), q($14)
      printf "\"host_rss_and_device_bytes_per_node\": %s, \"host_over_device\": %s", q($15), n($16)
      if (NF >= 19) {
        cell = $17; gsub(/^ +| +$/, "", cell)
        if (cell ~ /^device /) { sub(/^device /, "", cell); cpu = "null"; dev = n(cell) } else { cpu = q(cell); dev = "null" }
        printf ", \"floor_ms_scalar_vector\": %s, \"device_floor_ms\": %s, \"over_floor\": %s", cpu, dev, n($18)
      }
      printf "}"
    }' "$1"
}

# Catch2's summary of one test executable's log: "PASSED FAILED", or nothing when the log has none
# (the executable crashed or was stopped before it printed one).
catch_counts() {
  awk '
    /^All tests passed \(/ { for (i = 1; i <= NF; ++i) if ($i == "test") { p = $(i - 1); f = 0; found = 1 } }
    /^test cases:/ {
      p = 0; f = 0; found = 1
      for (i = 1; i <= NF; ++i) { if ($i == "passed") p = $(i - 1); if ($i == "failed") f = $(i - 1) }
    }
    END { if (found) print p + 0, f + 0 }' "$1"
}

# The names of the test cases a Catch2 log reports as failed, at most 20, as a JSON array. Catch2 prints
# each failure under a header: a line of 79 dashes, the test case's name (wrapped over several lines
# when long, then its sections, indented; joined here), another line of dashes; "FAILED:" follows.
catch_failed_names() {
  awk '
    BEGIN { dashes = "-------------------------------------------------------------------------------" }
    $0 == dashes { if (inside) { inside = 0; current = name } else { inside = 1; name = "" }; next }
    inside { line = $0; sub(/^ +/, "", line); name = name == "" ? line : name " " line; next }
    /FAILED:$/ && current != "" && !(current in seen) && count < 20 { seen[current] = 1; names[count++] = current }
    END {
      printf "["
      for (i = 0; i < count; ++i) { s = names[i]; gsub(/\\/, "\\\\", s); gsub(/"/, "\\\"", s); printf "%s\"%s\"", i ? ", " : "", s }
      printf "]"
    }' "$1"
}

# A timings file's foreground phases as one JSON object, name: wall seconds (a phase that ends more
# than once is summed), followed by ", \"pictures_background_s\": S" for the background phases.
timings_phases_json() {
  awk '
    match($0, /\{"name": "[^"]*", "wall": [-0-9.eE+]+, "cpu": [-0-9.eE+]+, "background": (true|false)\}/) {
      s = substr($0, RSTART, RLENGTH)
      name = s; sub(/^\{"name": "/, "", name); sub(/", "wall".*/, "", name)
      wall = s; sub(/.*"wall": /, "", wall); sub(/, "cpu".*/, "", wall)
      if (s ~ /"background": true/) { pictures += wall; next }
      if (!(name in sum)) order[count++] = name
      sum[name] += wall
    }
    END {
      printf "{"
      for (i = 0; i < count; ++i) printf "%s\"%s\": %.6f", i ? ", " : "", order[i], sum[order[i]]
      printf "}, \"pictures_background_s\": %.6f", pictures
    }' "$1"
}

# One top-level number or string of a timings file ("wall", "nodes", "backend", ...), raw.
timings_value() {
  sed -n "s/^  \"$1\": \\(.*\\),\$/\\1/p; s/^  \"$1\": \\(.*\\)\$/\\1/p" "$2" | head -n 1 | sed 's/^"\(.*\)"$/\1/'
}

# The whole-process wall time (fork to exit, median over the repeats) of the summary row of
# `pdmesh bench --whole-run` for case $1 in its log $2.
whole_run_wall() {
  awk -F'|' -v c="$1" '
    { k = $2; gsub(/^ +| +$/, "", k) }
    k == c && NF >= 10 { w = $7; split(w, parts, "/"); m = parts[2]; gsub(/ /, "", m); print m; exit }' "$2"
}

# A PDMESH_KERNEL_PROFILE file (a "kernel launches seconds" header, then tab-separated lines) as
# {"kernel": {"launches": N, "seconds": S}, ...}; {} when the file is missing.
kernel_profile_json() {
  [ -f "$1" ] || { printf '{}'; return; }
  awk -F'\t' 'NR > 1 && NF == 3 { printf "%s\"%s\": {\"launches\": %s, \"seconds\": %s}", n++ ? ", " : "{", $1, $2, $3 }
    END { printf n ? "}" : "{}" }' "$1"
}
