#!/usr/bin/env bash
# Writes the small test shapefiles of tests/data/geometry/gis/ with shapelib's own tools (Debian
# package `shapelib`: shpcreate, shpadd, dbfcreate, dbfadd). Each shapefile is .shp + .shx + .dbf.
#   lake.shp         Polygon: record 1 'lake shore' a 10 x 10 square (clockwise) with a 2 x 2 hole
#                    (counter-clockwise); record 2 'islet' a triangle in the hole
#   lake_z.shp       PolygonZ: the same square with z values, unnamed
#   roads.shp        Arc (PolyLine): 'road' of two parts, 'levee' of one
#   wells.shp        Point: two points only (a shapefile that bounds nothing)
# and tests/data/bad/points_only.shp, a MultiPoint file of points only (an input error).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=tests/data/geometry/gis
mkdir -p "$out"
cd "$out"
for f in lake lake_z roads wells; do rm -f "$f.shp" "$f.shx" "$f.dbf"; done

shpcreate lake polygon
shpadd lake 0 0 0 10 10 10 10 0 0 0 + 4 4 6 4 6 6 4 6 4 4
shpadd lake 4.5 4.5 4.5 5.5 5.5 4.5 4.5 4.5
dbfcreate lake -s name 20
dbfadd lake "lake shore"
dbfadd lake "islet"

shpcreate lake_z polygonz
shpadd lake_z -z 0 0 1 0 10 1 10 10 2 10 0 2 0 0 1
dbfcreate lake_z -n id 4 0
dbfadd lake_z 1

shpcreate roads arc
shpadd roads 1 1 3 3 + 3 3 8 2
shpadd roads 2 8 8 8
dbfcreate roads -s NAME 20
dbfadd roads road
dbfadd roads levee

shpcreate wells point
shpadd wells 2 2
shpadd wells 7 7
dbfcreate wells -s name 20
dbfadd wells w1
dbfadd wells w2

# A broken input of tests/data/bad (test_bad_inputs.cpp): points only.
cd ../../bad
rm -f points_only.shp points_only.shx points_only.dbf
shpcreate points_only multipoint
shpadd points_only 2 2 7 7
