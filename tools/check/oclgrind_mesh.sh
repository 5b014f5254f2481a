#!/usr/bin/env bash
# A short `pdmesh mesh` run on Oclgrind's simulated device (tools/check/oclgrind_check.sh: data races and
# API misuse fail it) whose final.nodes must equal the host reference's byte for byte.
#   tools/check/oclgrind_mesh.sh PDMESH CASE ITERATIONS WORK_DIR
set -euo pipefail
pdmesh=$1 case=$2 iterations=$3 work=$4
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work"
mkdir -p "$work"
common=(mesh "$case" --iterations "$iterations" --precision double --formats msh -q)
"$pdmesh" "${common[@]}" --device host --out "$work/host"
"$here/oclgrind_check.sh" "$pdmesh" "${common[@]}" --device opencl --out "$work/oclgrind"
if ! cmp "$work/host/final.nodes" "$work/oclgrind/final.nodes"; then
  echo "oclgrind_mesh: final.nodes on Oclgrind differs from the host reference's" >&2
  exit 1
fi
echo "oclgrind_mesh: final.nodes equals the host reference's ($(sed -n 2p "$work/host/final.nodes") nodes)"
rm -rf "$work"
