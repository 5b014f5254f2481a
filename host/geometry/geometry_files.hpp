// Reading the geometry of a case: one or more .crv/.dat/.poly files (or curves given in memory),
// optional curve names, validated and processed by build_geometry().
#pragma once
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/projection.hpp"

namespace pdmesh {

// Reads every file into one RawGeometry, curves in file order: by extension (case-insensitive) .crv,
// .dat (the count format, or a Selig/Lednicer airfoil as its first line says), .poly, .geojson/.json,
// .shp. Repairs a reader made (repeated airfoil points) are noted on the progress sink. With more than
// one airfoil file, each one's curve names get its file stem as prefix ("s1223_upper"). per_file (if
// given) receives "a.crv: 4 curves, b.poly: 1 curve" for messages. InputError for an unsupported
// extension; reader errors pass through.
RawGeometry read_geometry_files(const std::vector<std::string>& paths, std::string* per_file = nullptr);

// Reads every file (read_geometry_files), concatenates their curves in
// order, names them from curve_names (empty: default names "curve<k>"), and builds the geometry.
// InputError for an unsupported extension, a wrong number of names or a repeated name;
// reader and build_geometry errors pass through.
Geometry read_geometry(const std::vector<std::string>& paths, const std::vector<std::string>& curve_names,
                       const GeometryOptions& options = {});
// The same with geometry.projection: for ProjectionKind::Equirectangular the curves and points are
// checked to be lon/lat and projected (project_lonlat) before the geometry is built, and *used (if
// given) receives the projection, for mapping the outputs back.
Geometry read_geometry(const std::vector<std::string>& paths, const std::vector<std::string>& curve_names,
                       const GeometryOptions& options, ProjectionKind projection, Equirectangular* used);

// The same for curves given in memory (the Python API): names them from curve_names like
// read_geometry() (the same errors) and builds the geometry.
Geometry geometry_from_curves(std::vector<RawCurve> curves, const std::vector<std::string>& curve_names,
                              const GeometryOptions& options = {}, ProjectionKind projection = ProjectionKind::None,
                              Equirectangular* used = nullptr);

}  // namespace pdmesh
