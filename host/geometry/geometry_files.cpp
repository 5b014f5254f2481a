// read_geometry(): dispatches each geometry file to its reader by extension (and a .dat file by its
// content), applies the curve names and hands everything to build_geometry().
#include "geometry/geometry_files.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/progress_notes.hpp"
#include "geometry/airfoil_reader.hpp"
#include "geometry/curve_reader.hpp"
#include "geometry/geojson_reader.hpp"
#include "geometry/gis_features.hpp"
#include "geometry/poly_reader.hpp"
#include "geometry/reader_text.hpp"
#include "geometry/shapefile_reader.hpp"

namespace pdmesh {

namespace {

// Applies curve_names (empty: keep the default names) with the checks both entry points share;
// `per_file` describes where the curves came from, for the count message.
void name_curves(std::vector<RawCurve>& curves, const std::vector<std::string>& curve_names,
                 const std::string& per_file) {
  if (!curve_names.empty()) {
    if (curve_names.size() != curves.size()) {
      throw InputError(
          fmt::format("{} curve names given, but the geometry has {} curve{} ({}); give one name per "
                      "curve in file order, or none",
                      curve_names.size(), curves.size(), curves.size() == 1 ? "" : "s", per_file));
    }
    std::set<std::string> seen;
    for (std::size_t k = 0; k < curves.size(); ++k) {
      if (curve_names[k].empty()) throw InputError(fmt::format("curve name {} is empty", k));
      if (!seen.insert(curve_names[k]).second) {
        throw InputError(fmt::format("curve name '{}' is given twice (curve {})", curve_names[k], k));
      }
      curves[k].name = curve_names[k];
    }
  }
}

// A file name's stem as a plain curve-name prefix (gis::plain_name).
std::string plain_stem(const std::string& path) {
  const std::string stem = gis::plain_name(std::filesystem::path(path).stem().string());
  return stem.empty() ? std::string("airfoil") : stem;
}

}  // namespace

void append_geometry(RawGeometry& into, RawGeometry part) {
  const auto append = [](auto& to, auto& from) {
    for (auto& x : from) to.push_back(std::move(x));
  };
  append(into.curves, part.curves);
  append(into.holes, part.holes);
  append(into.points, part.points);
  append(into.regions, part.regions);
  append(into.notes, part.notes);
  append(into.groups, part.groups);
}

RawGeometry read_geometry_files(const std::vector<std::string>& paths, PolyHull hull, std::string* per_file,
                                const OtherGeometryFile& other) {
  if (paths.empty()) throw InputError("no geometry files given");
  RawGeometry raw;
  std::vector<std::pair<std::size_t, std::size_t>> airfoils;  // [first, last) curves of each airfoil file
  std::vector<std::string> airfoil_paths;
  std::string counts;  // "a.crv: 4 curves, b.poly: 1 curve", for the names message
  for (const std::string& path : paths) {
    const std::string ext = lower_extension(std::filesystem::path(path));
    const std::size_t before = raw.curves.size();
    if (ext == ".crv") {
      for (RawCurve& c : read_curve_file(path)) raw.curves.push_back(std::move(c));
    } else if (ext == ".dat") {
      const std::vector<detail::TokenLine> lines = detail::read_token_lines(path);
      if (is_count_format(lines)) {
        for (RawCurve& c : read_curve_file(path)) raw.curves.push_back(std::move(c));
      } else {
        AirfoilFile airfoil = read_airfoil_lines(path, lines);
        for (const std::string& note : airfoil.notes) progress_line("geometry: " + note);
        for (RawCurve& c : airfoil.curves) raw.curves.push_back(std::move(c));
        airfoils.emplace_back(before, raw.curves.size());
        airfoil_paths.push_back(path);
      }
    } else if (ext == ".poly") {
      PolyFile poly = read_poly_file(path, hull);
      for (RawCurve& c : poly.curves) raw.curves.push_back(std::move(c));
      for (RawHolePoint& h : poly.holes) raw.holes.push_back(std::move(h));
      for (RawPoint& p : poly.points) raw.points.push_back(std::move(p));
      for (GeometryRegion& r : poly.regions) raw.regions.push_back(std::move(r));
      for (std::string& n : poly.notes) raw.notes.push_back(std::move(n));
    } else if (ext == ".geojson" || ext == ".json" || ext == ".shp") {
      append_geometry(raw, ext == ".shp" ? read_shapefile(path) : read_geojson_file(path));
    } else if (std::optional<RawGeometry> part = other ? other(path, ext) : std::nullopt) {
      append_geometry(raw, std::move(*part));
    } else {
      throw InputError(
          fmt::format("{}: unsupported geometry file extension '{}' (supported: .crv, .dat, .poly, "
                      ".geojson, .json, .shp{})",
                      path, ext, other ? ", and the mesh files .msh, .vtu, .su2, .mesh, .ele" : ""));
    }
    const std::size_t n = raw.curves.size() - before;
    counts += fmt::format("{}{}: {} curve{}", counts.empty() ? "" : ", ", path, n, n == 1 ? "" : "s");
  }
  // Two airfoils would both have an `upper`: each name is prefixed by its file's stem.
  if (airfoils.size() > 1) {
    std::set<std::string> used;
    for (std::size_t a = 0; a < airfoils.size(); ++a) {
      std::string prefix = plain_stem(airfoil_paths[a]);
      for (int k = 2; !used.insert(prefix).second; ++k) prefix = fmt::format("{}{}", plain_stem(airfoil_paths[a]), k);
      for (std::size_t c = airfoils[a].first; c < airfoils[a].second; ++c)
        raw.curves[c].name = prefix + "_" + raw.curves[c].name;
    }
  }
  if (per_file != nullptr) *per_file = std::move(counts);
  return raw;
}

namespace {

// The steps after the naming: projection, the prepare step, build_geometry; the regions, notes and
// curve groups copied onto the result.
Geometry build_read_geometry(RawGeometry raw, const GeometryOptions& options, const ReadSteps& steps) {
  if (steps.projection == ProjectionKind::Equirectangular) {
    const Equirectangular p = project_lonlat(raw);
    if (steps.used != nullptr) *steps.used = p;
  }
  if (steps.prepare) steps.prepare(raw.curves, raw.holes);
  std::vector<GeometryRegion> regions = std::move(raw.regions);
  std::vector<std::string> notes = std::move(raw.notes);
  std::vector<CurveGroup> groups = std::move(raw.groups);
  Geometry g = build_geometry(std::move(raw), options);
  g.regions = std::move(regions);
  g.notes = std::move(notes);
  g.groups = std::move(groups);
  return g;
}

}  // namespace

Geometry read_geometry(const std::vector<std::string>& paths, const std::vector<std::string>& curve_names,
                       const GeometryOptions& options, const ReadSteps& steps) {
  std::string per_file;
  RawGeometry raw = read_geometry_files(paths, options.hull, &per_file, steps.other_files);
  name_curves(raw.curves, curve_names, per_file);
  return build_read_geometry(std::move(raw), options, steps);
}

Geometry geometry_from_curves(std::vector<RawCurve> curves, const std::vector<std::string>& curve_names,
                              const GeometryOptions& options, std::vector<RawPoint> points, const ReadSteps& steps) {
  if (curves.empty()) throw InputError("the geometry has no curves");
  name_curves(curves, curve_names, "given in memory");
  RawGeometry raw;
  raw.curves = std::move(curves);
  raw.points = std::move(points);
  return build_read_geometry(std::move(raw), options, steps);
}

}  // namespace pdmesh
