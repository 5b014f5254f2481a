// read_geometry(): dispatches each geometry file to its reader by extension, applies the curve
// names and hands everything to build_geometry().
#include "geometry/geometry_files.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "geometry/curve_reader.hpp"
#include "geometry/poly_reader.hpp"

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

}  // namespace

Geometry read_geometry(const std::vector<std::string>& paths, const std::vector<std::string>& curve_names,
                       const GeometryOptions& options) {
  if (paths.empty()) throw InputError("no geometry files given");
  std::vector<RawCurve> curves;
  std::vector<RawHolePoint> holes;
  std::string per_file;  // "a.crv: 4 curves, b.poly: 1 curve", for the names message
  for (const std::string& path : paths) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    const std::size_t before = curves.size();
    if (ext == ".crv" || ext == ".dat") {
      for (RawCurve& c : read_curve_file(path)) curves.push_back(std::move(c));
    } else if (ext == ".poly") {
      PolyFile poly = read_poly_file(path);
      for (RawCurve& c : poly.curves) curves.push_back(std::move(c));
      for (RawHolePoint& h : poly.holes) holes.push_back(std::move(h));
    } else {
      throw InputError(
          fmt::format("{}: unsupported geometry file extension '{}' (supported: .crv, .dat, .poly)", path, ext));
    }
    const std::size_t n = curves.size() - before;
    per_file += fmt::format("{}{}: {} curve{}", per_file.empty() ? "" : ", ", path, n, n == 1 ? "" : "s");
  }
  name_curves(curves, curve_names, per_file);
  return build_geometry(std::move(curves), holes, options);
}

Geometry geometry_from_curves(std::vector<RawCurve> curves, const std::vector<std::string>& curve_names,
                              const GeometryOptions& options, std::vector<RawPoint> points) {
  if (curves.empty()) throw InputError("the geometry has no curves");
  name_curves(curves, curve_names, "given in memory");
  return build_geometry(RawGeometry{std::move(curves), {}, std::move(points)}, options);
}

}  // namespace pdmesh
