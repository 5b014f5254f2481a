#!/usr/bin/env bash
# Checks that every tracked C++ and OpenCL C file is laid out as .clang-format says:
#   tools/check/format.sh          list the files that differ, exit 1 if any (ctest `format`, .ci/run)
#   tools/check/format.sh --fix    rewrite them in place
# clang-format's layout changes between major versions, so the check uses the one version
# tools/setup.sh installs (Debian 12's clang-format-14); another version is refused, not guessed.
set -euo pipefail
cd "$(dirname "$0")/../.."
want=14
tool=${CLANG_FORMAT:-$(command -v clang-format-$want || command -v clang-format || true)}
[ -n "$tool" ] || { echo "format.sh: clang-format-$want is not installed (tools/setup.sh --tests installs it)" >&2; exit 2; }
version=$("$tool" --version | sed -n 's/.*version \([0-9]*\)\..*/\1/p')
[ "$version" = "$want" ] || { echo "format.sh: $tool is version $version; the layout is defined by clang-format $want" >&2; exit 2; }
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.cl' | grep -v '^\.')
if [ "${1:-}" = --fix ]; then
  "$tool" -i --style=file "${files[@]}"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  "$tool" --style=file --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  echo "format.sh: ${#bad[@]} of ${#files[@]} files are not laid out as .clang-format says (tools/check/format.sh --fix rewrites them):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "format.sh: ${#files[@]} files laid out as .clang-format says"
