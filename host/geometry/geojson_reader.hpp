// Reader for GeoJSON (RFC 7946) files: FeatureCollection, Feature, GeometryCollection or a bare
// geometry, with nlohmann::json (docs/geometry-input.md, "GeoJSON and shapefiles").
#pragma once
#include <string>

#include "geometry/geometry.hpp"

namespace pdmesh {

// Polygon and MultiPolygon rings become closed curves, LineString and MultiLineString embedded
// constraints, Point and MultiPoint embedded points; a feature's `name` property names its curves.
// Coordinates are taken as given. InputError naming FILE:LINE:COLUMN and what the parser expected
// for malformed JSON, and FILE:LINE (the feature's) and the value for an unknown type, a bad
// position or a ring of fewer than 3 points.
RawGeometry read_geojson_file(const std::string& path);

// The same for GeoJSON text already in memory; `path` names it in messages.
RawGeometry read_geojson_text(const std::string& path, const std::string& text);

}  // namespace pdmesh
