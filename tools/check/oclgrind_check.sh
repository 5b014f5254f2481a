#!/usr/bin/env bash
# Runs a command under Oclgrind's simulated OpenCL device with the data-race detector and the API
# checker (docs/opencl.md, "Oclgrind"); fails when the command fails or Oclgrind reports anything.
#   tools/check/oclgrind_check.sh COMMAND [ARGS...]
# Not --uninitialized: Oclgrind 21.10 misreports memory filled by clEnqueueFillBuffer or written in
# parts by the host, and aborts on LLVM's `freeze` instruction (see the GPU portability audit).
set -uo pipefail
if ! command -v oclgrind >/dev/null; then
  echo "oclgrind_check: oclgrind is not installed (tools/setup.sh --tests installs it)" >&2
  exit 1
fi
log=$(mktemp)
trap 'rm -f "$log"' EXIT
oclgrind --data-races --check-api --max-errors 100 --log "$log" "$@"
status=$?
if [ -s "$log" ]; then
  echo "oclgrind_check: Oclgrind reported:" >&2
  cat "$log" >&2
  exit 1
fi
if [ $status -ne 0 ]; then
  echo "oclgrind_check: the command failed under Oclgrind (exit status $status)" >&2
  exit $status
fi
echo "oclgrind_check: no Oclgrind reports"
