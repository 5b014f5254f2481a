#!/usr/bin/env bash
# OpenFOAM's checkMesh on pdmesh's polyMesh (output format `openfoam`): a triangle mesh, a layered
# mesh of prisms and hexahedra and a two-material mesh must pass every check ("Mesh OK."), with the
# patches, types and cellZones the case asks for. Exit 77 (skipped) without checkMesh (Debian `openfoam`, tools/eval/setup_anchors.sh).
#
#   tools/eval/check_openfoam.sh PDMESH OUT_DIR
set -euo pipefail
pdmesh=$1
out=$2
command -v checkMesh >/dev/null || { echo "check_openfoam: no checkMesh; skipped"; exit 77; }
root="$(cd "$(dirname "$0")/../.." && pwd)"
rm -rf "$out"
mkdir -p "$out"

# Debian's OpenFOAM finds its own settings (etc/controlDict) through WM_PROJECT_DIR.
[ -n "${WM_PROJECT_DIR:-}" ] || [ ! -d /usr/share/openfoam/etc ] || export WM_PROJECT_DIR=/usr/share/openfoam

# The system/ files a case needs for checkMesh to open it (no solver runs).
foam_dict() {  # CLASS OBJECT BODY
  printf 'FoamFile\n{\n    version 2.0;\n    format ascii;\n    class %s;\n    object %s;\n}\n%s\n' "$1" "$2" "$3"
}

check() {  # NAME CASE [ARGS...]: mesh the case, run checkMesh on its polyMesh in a scratch case
  local name=$1 case=$2
  shift 2
  "$pdmesh" mesh "$case" --out "$out/$name" --formats openfoam -q "$@"
  local dir="$out/$name/mesh_openfoam"
  mkdir -p "$dir/system"
  foam_dict dictionary controlDict 'application simpleFoam; startFrom startTime; startTime 0; stopAt endTime;
endTime 1; deltaT 1; writeControl timeStep; writeInterval 1;' > "$dir/system/controlDict"
  foam_dict dictionary fvSchemes 'ddtSchemes {} gradSchemes {} divSchemes {} laplacianSchemes {}
interpolationSchemes {} snGradSchemes {}' > "$dir/system/fvSchemes"
  foam_dict dictionary fvSolution 'solvers {}' > "$dir/system/fvSolution"
  checkMesh -case "$dir" > "$out/$name.log" 2>&1 || { cat "$out/$name.log"; echo "check_openfoam: $name: checkMesh failed"; exit 1; }
  grep -q "^Mesh OK\." "$out/$name.log" || { cat "$out/$name.log"; echo "check_openfoam: $name: not 'Mesh OK.'"; exit 1; }
  echo "check_openfoam: $name: $(grep -E '^ +cells:' "$out/$name.log" | tr -s ' '), Mesh OK."
}

check naca0012 "$root/cases/naca0012/case.toml" --set 'output.walls=["upper", "lower"]'
for patch in upper lower; do
  grep -A2 -E "^ +$patch\$" "$out/naca0012/mesh_openfoam/constant/polyMesh/boundary" | grep -q "type            wall;" \
    || { echo "check_openfoam: naca0012: the $patch patch is not a wall"; exit 1; }
done
check layered "$root/tests/data/interop/layered.toml"
grep -c "type            wall;" "$out/layered/mesh_openfoam/constant/polyMesh/boundary" | grep -qv '^0$' \
  || { echo "check_openfoam: layered: no wall patch"; exit 1; }
grep -q "hexahedra: *[1-9]" "$out/layered.log" || { echo "check_openfoam: layered: no hexahedra"; exit 1; }
# Two materials from a Gmsh file: one patch for the physical group 'walls' (two curves), the
# materials as cellZones.
check regions "$root/tests/data/keep_tags/two_materials.msh" --set 'output.walls=["walls"]'
poly="$out/regions/mesh_openfoam/constant/polyMesh"
grep -c "type            wall;" "$poly/boundary" | grep -q '^1$' || { echo "check_openfoam: regions: not one wall patch"; exit 1; }
for zone in steel copper; do
  grep -q "^$zone\$" "$poly/cellZones" || { echo "check_openfoam: regions: no cellZone $zone"; exit 1; }
done
echo "check_openfoam: passed"
