// What the GIS readers (GeoJSON, shapefiles) share: features turned into RawGeometry parts with the
// naming rules of docs/geometry-input.md ("GeoJSON and shapefiles"): polygon rings become closed
// curves (outer ring NAME, holes NAME_hole1 ...), lines become embedded constraints, points
// embedded points; repeated names are made distinct at the end.
#pragma once
#include <string>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh::gis {

// Where a feature came from, for names and messages.
struct FeatureSource {
  std::string file;
  int line = 0;      // the feature's line (GeoJSON) or record number (shapefile)
  std::string name;  // plain name (plain_name) or empty
  std::string what;  // "feature 3 ('lake')", for messages
};

// A name made plain for node and mesh files: each character other than a letter, digit, _ . + -
// becomes '_'.
std::string plain_name(const std::string& name);

// One polygon: rings[0] the outer ring, the rest holes; `part` > 0 numbers the polygons of a
// multi-polygon (NAME_1, NAME_2 ...). Consecutive repeated positions are dropped (noted on the
// progress sink), the ring is closed if its last position is not its first. InputError naming the
// file, line, ring and count for a ring of fewer than 3 distinct points.
void add_polygon(RawGeometry& out, const FeatureSource& src, int part, std::vector<std::vector<Vec2>> rings);
// An open (or closed) polyline, as an embedded constraint; InputError for fewer than 2 distinct points.
void add_line(RawGeometry& out, const FeatureSource& src, int part, std::vector<Vec2> points);
void add_point(RawGeometry& out, const FeatureSource& src, Vec2 p);

// After the last feature: repeated names get _1, _2 ... in order (skipping names taken), and a file
// with no polygon or line (points only, or nothing) is an InputError naming the file.
void finish(RawGeometry& out, const std::string& file, std::size_t first_curve, std::size_t first_point);

}  // namespace pdmesh::gis
