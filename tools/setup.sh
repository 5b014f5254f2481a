#!/usr/bin/env bash
# Installs what pdmesh needs from Debian's packages (skipping what is already installed), creates the
# Python virtual environment .venv (build tools, numpy and pytest from PyPI), configures and builds
# Release into build/ (the command, the tests and the Python extension), then installs the Python
# package into .venv from that same build. Idempotent and quick when nothing changed; safe to run again.
# PDMESH_NO_PYTHON=1 leaves Python out (the C++ build and its tests never need it).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake g++ make pkg-config python3
          ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo oclgrind hyperfine
          catch2 libgmp-dev libfmt-dev libcli11-dev libtomlplusplus-dev libmuparser-dev libcairo2-dev zlib1g-dev)
[ -n "${PDMESH_NO_PYTHON:-}" ] || packages+=(python3-venv python3-dev)
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
  # without a second compile), numpy, pytest and the extras the tests use (meshio, matplotlib,
  # shapely); pip leaves what is already there.
  "$venv/bin/python" -m pip install -q --disable-pip-version-check \
    "scikit-build-core>=0.10" "nanobind>=2.0" "numpy>=1.21" "pytest>=7" "meshio>=5" "matplotlib>=3.5" "shapely>=1.8"
  python_args=(-DPDMESH_PYTHON=ON "-DPython_EXECUTABLE=$venv/bin/python")
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${python_args[@]}" ${PDMESH_CMAKE_ARGS:-}
cmake --build build -j "$jobs"

site=
[ -n "${PDMESH_NO_PYTHON:-}" ] || site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["platlib"])')
if [ -n "$site" ] && diff -rq --exclude=__pycache__ build/python/pdmesh "$site/pdmesh" >/dev/null 2>&1 &&
   [ -x "$venv/bin/pdmesh" ]; then
  echo "setup: the Python package in .venv is up to date"
elif [ -n "$site" ]; then
  # pip builds the wheel in build/ itself (scikit-build-core reuses the configured tree, so nothing is
  # compiled again), with build/'s generator and its tests kept on.
  generator=$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' build/CMakeCache.txt)
  CMAKE_GENERATOR=$generator CMAKE_BUILD_PARALLEL_LEVEL=$jobs "$venv/bin/python" -m pip install -q \
    --disable-pip-version-check --no-build-isolation --no-deps \
    -Cbuild-dir=build -Ccmake.define.PDMESH_BUILD_TESTS=ON .
  echo "setup: Python package installed in .venv ($("$venv/bin/python" -c 'import pdmesh; print("pdmesh", pdmesh.__version__)'))"
fi
