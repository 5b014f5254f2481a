// Reading the geometry of a case: one or more .crv/.dat/.poly files (or curves given in memory),
// optional curve names, validated and processed by build_geometry().
#pragma once
#include <string>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

// Reads every file (by extension: .crv, .dat, .poly; case-insensitive), concatenates their curves in
// order, names them from curve_names (empty: default names "curve<k>"), and builds the geometry.
// InputError for an unsupported extension, a wrong number of names or a repeated name;
// reader and build_geometry errors pass through.
Geometry read_geometry(const std::vector<std::string>& paths, const std::vector<std::string>& curve_names,
                       const GeometryOptions& options = {});

// The same for curves given in memory (the Python API): names them from curve_names like
// read_geometry() (the same errors) and builds the geometry, with the embedded `points`.
Geometry geometry_from_curves(std::vector<RawCurve> curves, const std::vector<std::string>& curve_names,
                              const GeometryOptions& options = {}, std::vector<RawPoint> points = {});

}  // namespace pdmesh
