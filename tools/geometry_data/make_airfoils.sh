#!/usr/bin/env bash
# Writes the airfoil test files of tests/data/geometry/airfoils/ from the UIUC airfoil coordinate
# database as the aerosandbox wheel ships it (PyPI aerosandbox 4.2.10, aerosandbox/geometry/airfoil/
# airfoil_database/): three Selig files copied as they are, and naca2412 rewritten in Lednicer's
# layout by selig_to_lednicer.py (the wheel ships no Lednicer file). Nothing is edited by hand.
#   tools/geometry_data/make_airfoils.sh [WORKDIR]     (default /tmp/pdmesh-airfoils; needs pip and unzip)
set -euo pipefail
cd "$(dirname "$0")/../.."
work=${1:-/tmp/pdmesh-airfoils}
out=tests/data/geometry/airfoils
mkdir -p "$work" "$out"
wheel=$work/aerosandbox-4.2.10-py3-none-any.whl
[ -f "$wheel" ] || python3 -m pip download -q --no-deps -d "$work" aerosandbox==4.2.10
db=aerosandbox/geometry/airfoil/airfoil_database
unzip -q -o "$wheel" "$db/s1223.dat" "$db/naca2412.dat" "$db/e387.dat" -d "$work"
for f in s1223 naca2412 e387; do cp "$work/$db/$f.dat" "$out/$f.dat"; done
python3 tools/geometry_data/selig_to_lednicer.py "$work/$db/naca2412.dat" > "$out/naca2412_lednicer.dat"
