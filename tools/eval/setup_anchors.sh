#!/usr/bin/env bash
# Installs the anisotropic anchors that tools/eval/aniso_anchors.py runs, apart from the product's
# dependencies: BAMG inside FreeFem++ (Debian `freefem++`) and, in the virtual environment
# tools/.venv-anchors, Gmsh 4.15.2 and mmg2d (PyPI `mmgpy`, whose wheel ships the mmg2d_O3 binary)
# with numpy for the evaluator, and the third-party readers tools/eval/motion_check.py opens a motion
# run's .pvd with (pyvista with its vtk wheel, meshio). Idempotent.
#
#   tools/eval/setup_anchors.sh
#   tools/.venv-anchors/bin/python tools/eval/aniso_anchors.py
set -euo pipefail
cd "$(dirname "$0")/../.."

if ! command -v FreeFem++ >/dev/null; then
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends freefem++
fi

venv=$PWD/tools/.venv-anchors
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check "numpy>=1.21" "gmsh==4.15.2" "mmgpy==0.17.1" \
  "pyvista==0.49.1" "meshio==5.3.5"
ls "$venv/bin/mmg2d_O3" >/dev/null
echo "setup_anchors: FreeFem++ $(command -v FreeFem++), gmsh $("$venv/bin/python" -c 'import gmsh; print(gmsh.__version__)'), mmg2d $venv/bin/mmg2d_O3"
