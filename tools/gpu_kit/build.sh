#!/usr/bin/env bash
# Stages gpu-kit/ at the project root (ignored by git): the pdmesh command and the device-test
# executables with every shared library they need that is not glibc beside them (RUNPATH $ORIGIN, set
# with patchelf), ocl-icd's OpenCL ICD loader among them, the case files, and run.sh with its parts
# (tools/gpu_kit/). It is what one `run` call on a bare GPU machine carries (docs/devices.md, "The GPU
# kit"). Needs build/ configured (tools/setup.sh); builds the targets it takes itself.
#   tools/gpu_kit/build.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"

# The device-test executables the kit runs (tests/test_*.cpp that need an OpenCL device).
TESTS=(test_device_boundary test_device_cases test_device_clearance test_device_floor test_device_momentum
       test_device_neighbours test_device_row_offsets test_device_simulation test_opencl_canary test_opencl_commands
       test_opencl_infra test_step_backends)
# glibc's own libraries: the machine's are used (they cannot be carried; BUILD_INFO names the oldest
# glibc the kit runs on).
GLIBC='^(linux-vdso|ld-linux-x86-64|libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|libanl|libnsl)\.so'
# What one run call carries at most (the working tree and the kit together), and what the kit may use.
CARRY_LIMIT=$((64 * 1024 * 1024))

if [ ! -f build/CMakeCache.txt ]; then
  echo "gpu_kit/build.sh: build/ is not configured; run tools/setup.sh first" >&2
  exit 2
fi
if ! command -v patchelf >/dev/null; then
  echo "gpu_kit/build.sh: installing patchelf (Debian package) to set the kit's RUNPATH"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends patchelf
fi

if grep -q '^PDMESH_BUILD_TESTS:BOOL=OFF' build/CMakeCache.txt; then
  echo "gpu_kit/build.sh: build/ has the tests off; turning them on (the kit carries the device tests)"
  cmake -S . -B build -DPDMESH_BUILD_TESTS=ON >/dev/null
fi
cmake --build build -j "$(nproc 2>/dev/null || echo 2)" --target pdmesh "${TESTS[@]}"

stage=$(mktemp -d "$root/.gpu-kit-stage.XXXXXX")
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin"
binaries=(build/pdmesh)
for t in "${TESTS[@]}"; do binaries+=("build/tests/$t"); done
for b in "${binaries[@]}"; do
  install -m 755 "$b" "$stage/bin/"
  strip --strip-unneeded "$stage/bin/$(basename "$b")"
done

# Every library ldd resolves for any of the binaries (ldd lists the dependencies of dependencies too),
# glibc's left out; copied under its soname.
declare -A libs=()
for b in "${binaries[@]}"; do
  while read -r soname path; do
    [[ $soname =~ $GLIBC ]] && continue
    libs[$soname]=$path
  done < <(ldd "$b" | awk '$2 == "=>" && $3 ~ /^\// { print $1, $3 }')
done
for soname in "${!libs[@]}"; do
  install -m 644 "$(readlink -f "${libs[$soname]}")" "$stage/bin/$soname"
  strip --strip-unneeded "$stage/bin/$soname"
done
for f in "$stage"/bin/*; do patchelf --set-rpath '$ORIGIN' "$f"; done

# Every dependency resolves inside the kit or to glibc, with no help from the environment.
bad=$(for f in "$stage"/bin/*; do env -i PATH=/usr/bin:/bin ldd "$f" | awk -v d="$stage/bin/" '$2 == "=>" { print $1, $3 }' |
        grep -Ev "^[^ ]+ $stage/bin/" | grep -Ev "$GLIBC" || true; done | sort -u)
if [ -n "$bad" ]; then
  echo "gpu_kit/build.sh: dependencies outside the kit:" >&2
  echo "$bad" >&2
  exit 1
fi

git ls-files -z cases | xargs -0 cp --parents -t "$stage"
install -m 755 tools/gpu_kit/run.sh "$stage/run.sh"
install -m 644 tools/gpu_kit/kit_json.sh tools/gpu_kit/kit_driver.sh tools/gpu_kit/kit_steps.sh "$stage/"

# The newest glibc symbol version each file uses (GLIBC_NEEDS, read by run.sh: on an older glibc it
# leaves out the bundled libraries that need a newer one, so that the machine's own are used).
for f in "$stage"/bin/*; do
  echo "$(basename "$f") $(objdump -T "$f" | grep -o 'GLIBC_[0-9][0-9.]*' | sed 's/GLIBC_//' | sort -uV | tail -n 1)"
done >"$stage/GLIBC_NEEDS"
glibc_min=$(grep -v '^lib' "$stage/GLIBC_NEEDS" | cut -d' ' -f2 | sort -V | tail -n 1)
glibc_all=$(cut -d' ' -f2 "$stage/GLIBC_NEEDS" | sort -V | tail -n 1)
{
  echo "commit=$(git rev-parse HEAD)"
  echo "uncommitted_changes=$(git status --porcelain --untracked-files=no | wc -l)"
  echo "built=$(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "built_on=$(. /etc/os-release 2>/dev/null && echo "$PRETTY_NAME"), glibc $(getconf GNU_LIBC_VERSION | cut -d' ' -f2)"
  echo "glibc_min=$glibc_min"
  echo "glibc_for_all_bundled_libraries=$glibc_all"
  echo "newer_glibc_needed_by=$(while read -r f v; do
    [ "$(printf '%s\n%s\n' "$v" "$glibc_min" | sort -V | tail -n 1)" = "$glibc_min" ] || printf '%s ' "$f"
  done <"$stage/GLIBC_NEEDS")"
  echo "ocl_icd=$(dpkg-query -W -f='${Version}' ocl-icd-libopencl1 2>/dev/null || echo unknown)"
  echo "binaries=pdmesh ${TESTS[*]}"
} >"$stage/BUILD_INFO"

# The run call carries the working tree (tracked files and untracked ones git does not ignore) and
# the kit: together within the limit.
kit_bytes=$(du -sb "$stage" | cut -f1)
tree_bytes=$(git ls-files -z -co --exclude-standard | xargs -0 stat -c %s 2>/dev/null | awk '{ s += $1 } END { print s + 0 }')
if ((kit_bytes + tree_bytes > CARRY_LIMIT)); then
  echo "gpu_kit/build.sh: the kit ($kit_bytes bytes) and the working tree ($tree_bytes bytes) exceed the 64 MiB a run call carries" >&2
  exit 1
fi
rm -rf gpu-kit
mv "$stage" gpu-kit
trap - EXIT
echo "gpu_kit/build.sh: gpu-kit/ staged: $(du -sh gpu-kit | cut -f1) ($kit_bytes bytes; with the working tree's $tree_bytes, $(((kit_bytes + tree_bytes) * 100 / CARRY_LIMIT))% of the 64 MiB a run call carries), $(ls gpu-kit/bin | wc -l) files in bin/, glibc $glibc_min or newer ($glibc_all for every bundled library)"
