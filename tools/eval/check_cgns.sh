#!/usr/bin/env bash
# The CGNS library's own checker on pdmesh's CGNS files: `cgnscheck` (Debian cgns-convert,
# tools/setup.sh --tests) must read each file and report no error. Exit 77 (skipped) without cgnscheck.
#
#   tools/eval/check_cgns.sh FILE.cgns...
set -euo pipefail
command -v cgnscheck >/dev/null || { echo "check_cgns: no cgnscheck; skipped"; exit 77; }
status=0
for file in "$@"; do
  log=$(cgnscheck "$file" 2>&1) || { echo "$log"; echo "check_cgns: $file: cgnscheck failed"; status=1; continue; }
  if grep -qi "error" <<<"$log"; then
    echo "$log"
    echo "check_cgns: $file: cgnscheck reports errors"
    status=1
    continue
  fi
  echo "check_cgns: $file: no errors, $(grep -c '^WARNING' <<<"$log" || true) warnings"
done
exit $status
