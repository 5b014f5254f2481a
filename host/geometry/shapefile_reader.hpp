// Reader for ESRI shapefiles (.shp, with its .shx index and, for names, its .dbf table) through
// shapelib (docs/geometry-input.md, "GeoJSON and shapefiles").
#pragma once
#include <string>

#include "geometry/geometry.hpp"

namespace pdmesh {

// Polygon records (rings: a clockwise ring starts a polygon, the counter-clockwise rings after it
// are its holes) become closed curves, PolyLine records embedded constraints, Point and MultiPoint
// records embedded points; Z and M variants alike (z and m ignored). A `name` field of the .dbf
// (any case) names a record's curves. Messages give the record number (1-based) where the text
// readers give a line. InputError naming the file for a file shapelib cannot open, a MultiPatch,
// a shapefile of points only, and a ring of fewer than 3 points.
RawGeometry read_shapefile(const std::string& path);

}  // namespace pdmesh
