#!/usr/bin/env bash
# Sets pdmesh up on Debian 12: installs the Debian packages it needs (skipping what is already
# installed), creates the Python virtual environment .venv (build tools and numpy from PyPI),
# configures a Release build in build/, builds the command and the Python extension, and installs
# the Python package into .venv from that same build. Idempotent and quick when nothing changed.
#
#   tools/setup.sh            what the main job needs: build/pdmesh and the Python package
#   tools/setup.sh --tests    also the test suite: its Debian packages (Catch2, GMP, Oclgrind, clang-format, the CGNS tools), pytest
#                             and the optional Python extras, and every test executable and tool
#
# PDMESH_NO_PYTHON=1 leaves Python out (the command and the C++ tests never need it);
# PDMESH_CMAKE_ARGS adds arguments to the configure step. ccache is used when installed.
set -euo pipefail
cd "$(dirname "$0")/.."

tests=
for arg in "$@"; do
  case $arg in
    --tests) tests=1 ;;
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "setup: unknown argument '$arg' (use --tests or --help)" >&2; exit 2 ;;
  esac
done

packages=(cmake g++ make pkg-config python3
          ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
          libfmt-dev libcli11-dev libtomlplusplus-dev libmuparser-dev libcairo2-dev zlib1g-dev
          nlohmann-json3-dev libshp-dev libcgns-dev)
[ -n "${PDMESH_NO_PYTHON:-}" ] || packages+=(python3-venv python3-dev)
[ -z "$tests" ] || packages+=(catch2 libgmp-dev oclgrind hyperfine clang-format-14 libbenchmark-dev cgns-convert)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

python_args=()
if [ -z "${PDMESH_NO_PYTHON:-}" ]; then
  venv=$PWD/.venv
  [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
  # The build requirements of pyproject.toml (installed here so that the package builds from build/
  # without a second compile) and numpy; with --tests also pytest and the extras the tests use
  # (meshio, matplotlib, shapely; scikit-fem for examples/adapt_poisson.py). pip leaves what is already there.
  requirements=("scikit-build-core>=0.10" "nanobind>=2.0" "numpy>=1.21")
  [ -z "$tests" ] || requirements+=("pytest>=7" "meshio>=5" "matplotlib>=3.5" "shapely>=1.8" "scikit-fem>=10")
  "$venv/bin/python" -m pip install -q --disable-pip-version-check "${requirements[@]}"
  python_args=(-DPDMESH_PYTHON=ON "-DPython_EXECUTABLE=$venv/bin/python")
fi

# The test suite is configured once --tests has asked for it and stays configured: a later plain run
# builds only the main job's targets, and leaves the built tests as they are.
tests_arg=()
if [ -n "$tests" ]; then
  tests_arg=(-DPDMESH_BUILD_TESTS=ON)
elif [ ! -f build/CMakeCache.txt ]; then
  tests_arg=(-DPDMESH_BUILD_TESTS=OFF)
fi

jobs=$(nproc 2>/dev/null || echo 2)
# shellcheck disable=SC2086  # PDMESH_CMAKE_ARGS is a list of arguments
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${python_args[@]}" "${tests_arg[@]}" ${PDMESH_CMAKE_ARGS:-}
if [ -n "$tests" ]; then
  cmake --build build -j "$jobs"
else
  targets=(pdmesh)
  [ -n "${PDMESH_NO_PYTHON:-}" ] || targets+=(_core _core_stub pdmesh_python_files)
  cmake --build build -j "$jobs" --target "${targets[@]}"
fi

site=
[ -n "${PDMESH_NO_PYTHON:-}" ] || site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["platlib"])')
if [ -n "$site" ] && diff -rq --exclude=__pycache__ build/python/pdmesh "$site/pdmesh" >/dev/null 2>&1 &&
   [ -x "$venv/bin/pdmesh" ]; then
  echo "setup: the Python package in .venv is up to date"
elif [ -n "$site" ]; then
  # pip builds the wheel in build/ itself (scikit-build-core reuses the configured tree and builds only
  # the extension's targets, already built above, so nothing is compiled again), keeping build/'s
  # generator and its test setting.
  generator=$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' build/CMakeCache.txt)
  build_tests=$(sed -n 's/^PDMESH_BUILD_TESTS:BOOL=//p' build/CMakeCache.txt)
  CMAKE_GENERATOR=$generator CMAKE_BUILD_PARALLEL_LEVEL=$jobs "$venv/bin/python" -m pip install -q \
    --disable-pip-version-check --no-build-isolation --no-deps \
    -Cbuild-dir=build "-Ccmake.define.PDMESH_BUILD_TESTS=${build_tests:-OFF}" .
  echo "setup: Python package installed in .venv ($("$venv/bin/python" -c 'import pdmesh; print("pdmesh", pdmesh.__version__)'))"
fi
