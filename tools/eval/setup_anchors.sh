#!/usr/bin/env bash
# Installs the anisotropic anchors that tools/eval/aniso_anchors.py runs, apart from the product's
# dependencies: BAMG inside FreeFem++ (Debian `freefem++`), OpenFOAM's checkMesh (Debian `openfoam`) and, in the virtual environment
# tools/.venv-anchors, Gmsh 4.15.2 and mmg2d (PyPI `mmgpy`, whose wheel ships the mmg2d_O3 binary)
# with numpy for the evaluator, the coastal formats' third-party readers, and those
# tools/eval/motion_check.py opens a motion run's .pvd with (pyvista with its vtk wheel, meshio). Idempotent.
#
#   tools/eval/setup_anchors.sh
#   tools/.venv-anchors/bin/python tools/eval/aniso_anchors.py
set -euo pipefail
cd "$(dirname "$0")/../.."

# Debian `time` gives tools/bench/scale_vs_gmsh.py each command's peak RSS (/usr/bin/time -v); Debian
# `openfoam` gives tools/eval/check_openfoam.sh OpenFOAM's checkMesh.
if ! command -v FreeFem++ >/dev/null || [ ! -x /usr/bin/time ] || ! command -v checkMesh >/dev/null; then
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends freefem++ time openfoam
fi

venv=$PWD/tools/.venv-anchors
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check "numpy>=1.21" "gmsh==4.15.2" "mmgpy==0.17.1" \
  "pyvista==0.49.1" "meshio==5.3.5"
# Third-party readers of the coastal formats (tools/eval/check_coastal_formats.py): py2dm for .2dm and
# adcircpy's fort.14 parser, which needs only pandas (< 3: it passes delim_whitespace) and pyproj; the
# package's other dependencies are not installed.
"$venv/bin/python" -m pip install -q --disable-pip-version-check "py2dm==0.2.2" "pandas<3" "pyproj"
"$venv/bin/python" -m pip install -q --disable-pip-version-check --no-deps "adcircpy==1.2.7"
# shapely for the user corpus: tools/cases/make_user_corpus.py (the GSHHS clip) and
# tools/eval/corpus_anchors.py (the inputs' domains for Gmsh and the constraint check).
"$venv/bin/python" -m pip install -q --disable-pip-version-check "shapely==2.2.0"
# scikit-fem (with scipy) for tools/eval/periodic_homogenization.py: the periodic cell's effective
# conductivity on pdmesh's and Gmsh's periodic meshes, the pairs tying the periodic DOFs.
"$venv/bin/python" -m pip install -q --disable-pip-version-check "scikit-fem==12.0.2"
ls "$venv/bin/mmg2d_O3" >/dev/null
echo "setup_anchors: FreeFem++ $(command -v FreeFem++), gmsh $("$venv/bin/python" -c 'import gmsh; print(gmsh.__version__)'), mmg2d $venv/bin/mmg2d_O3"
