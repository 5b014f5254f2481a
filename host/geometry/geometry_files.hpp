// Reading the geometry of a case: one or more geometry files (or curves given in memory), optional
// curve names, the projection of lon/lat input and a step on the raw curves (healing), validated and
// processed by build_geometry().
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/projection.hpp"

namespace pdmesh {

// Called on the named raw curves just before build_geometry (healing, geometry/heal.hpp), with the
// hole points read with them.
using PrepareCurves = std::function<void(std::vector<RawCurve>&, const std::vector<RawHolePoint>&)>;

// Reads a geometry file of an extension the readers here do not know: a mesh file, read by
// io/mesh_geometry, which this layer cannot include. nullopt when it does not take the extension
// `ext` (lower case, with the dot).
using OtherGeometryFile = std::function<std::optional<RawGeometry>(const std::string& path, const std::string& ext)>;

// Appends everything `part` holds (curves, holes, points, regions, notes, curve groups) to `into`.
void append_geometry(RawGeometry& into, RawGeometry part);

// What reading does beyond the files.
struct ReadSteps {
  // geometry.projection: for Equirectangular the curves and points are checked to be lon/lat and
  // projected (project_lonlat) before anything else, and *used (if given) receives the projection,
  // for mapping the outputs back.
  ProjectionKind projection = ProjectionKind::None;
  Equirectangular* used = nullptr;
  PrepareCurves prepare;  // after the projection, before build_geometry
  // Files of other extensions (mesh files: io/mesh_geometry.hpp's mesh_geometry_files); empty: none.
  OtherGeometryFile other_files;
};

// Reads every file into one RawGeometry, curves in file order: by extension (case-insensitive) .crv,
// .dat (the count format, or a Selig/Lednicer airfoil as its first line says), .poly (Triangle's
// semantics, with `hull`), .geojson/.json, .shp. Repairs a reader made (repeated airfoil points) are
// noted on the progress sink. With more than one airfoil file, each one's curve names get its file
// stem as prefix ("s1223_upper"); any other extension by `other` (if given). per_file (if given)
// receives "a.crv: 4 curves, b.poly: 1 curve" for messages. InputError for an unsupported extension;
// reader errors pass through.
RawGeometry read_geometry_files(const std::vector<std::string>& paths, PolyHull hull = PolyHull::Automatic,
                                std::string* per_file = nullptr, const OtherGeometryFile& other = {});

// Reads every file (read_geometry_files), names the curves from curve_names (empty: default names
// "curve<k>"), applies `steps` (steps.other_files reads the extensions the readers here do not) and builds the geometry
// with its constraints, points, regions and notes. InputError for an unsupported extension, a wrong number of names or
// a repeated name; reader and build_geometry errors pass through.
Geometry read_geometry(const std::vector<std::string>& paths, const std::vector<std::string>& curve_names,
                       const GeometryOptions& options = {}, const ReadSteps& steps = {});

// The same for curves given in memory (the Python API): names them from curve_names like
// read_geometry() (the same errors), applies `steps` and builds the geometry, with the embedded
// `points`.
Geometry geometry_from_curves(std::vector<RawCurve> curves, const std::vector<std::string>& curve_names,
                              const GeometryOptions& options = {}, std::vector<RawPoint> points = {},
                              const ReadSteps& steps = {});

}  // namespace pdmesh
