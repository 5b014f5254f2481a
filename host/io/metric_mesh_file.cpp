// Metric data on a .vtu or .msh background mesh: the mesh readers' point-data array of 3 components.
#include "io/metric_mesh_file.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mixed_mesh.hpp"
#include "io/msh_reader.hpp"
#include "io/vtu_reader.hpp"

namespace pdmesh {

MetricMeshData load_metric_mesh(const std::filesystem::path& file, const std::string& array) {
  const std::string ext = lower_extension(file);
  if (ext != ".vtu" && ext != ".msh") {
    throw InputError(
        fmt::format("{}: a metric background mesh must be a .vtu or .msh file, or a Medit .mesh with its .sol "
                    "(got '{}')",
                    file.string(), ext));
  }
  MeshPointData pd;
  pd.wanted = array;
  MeshReadReport report;
  SurfaceCells cells;
  Mesh mesh = with_quads_split(
      ext == ".vtu" ? read_vtu(file, report, &pd, &cells) : read_msh(file, report, &pd, &cells), cells);
  const std::string name = file.string();
  if (mesh.triangles.empty()) {
    throw InputError(fmt::format(
        "{}: the mesh has no triangles{}; a metric background mesh needs triangle cells", name,
        report.skipped_elements > 0 ? fmt::format(" (it has {} other cells)", report.skipped_elements) : ""));
  }
  if (!pd.array) {
    const std::string has = pd.point_arrays.empty()
                                ? std::string("the file has no point data")
                                : fmt::format("its point-data arrays are: {}", fmt::join(pd.point_arrays, ", "));
    throw InputError(fmt::format("{}: no point-data array '{}' (the metric's m11 m12 m22); {}", name, array, has));
  }
  const PointDataArray& a = *pd.array;
  if (a.components != 3) {
    throw InputError(fmt::format("{}: point-data array '{}' has {} component{}; a metric needs 3 (m11 m12 m22)",
                                 a.where, array, a.components, a.components == 1 ? "" : "s"));
  }
  const std::size_t n = mesh.points.size();
  if (a.values.size() != 3 * n) {
    throw InputError(fmt::format("{}: point-data array '{}' has {} values for {} points (3 each)", a.where, array,
                                 a.values.size(), n));
  }
  std::vector<char> used(n, 0);
  for (const auto& t : mesh.triangles)
    for (int v : t) used[static_cast<std::size_t>(v)] = 1;
  auto label = [&](std::size_t i) {
    return i < pd.point_ids.size() ? fmt::format("node {}", pd.point_ids[i]) : fmt::format("point {}", i);
  };
  MetricMeshData d;
  d.metrics.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 p = mesh.points[i];
    if (!a.given.empty() && !a.given[i]) {
      if (used[i])
        throw InputError(fmt::format("{}: '{}' has no value for {} ({}, {}), a vertex of a triangle", a.where, array,
                                     label(i), p.x, p.y));
      continue;  // a point of no triangle is never interpolated: the identity stands in
    }
    const Metric m{a.values[3 * i], a.values[3 * i + 1], a.values[3 * i + 2]};
    check_metric(m, fmt::format("{}: '{}' at {} ({}, {})", a.where, array, label(i), p.x, p.y));
    d.metrics[i] = m;
  }
  d.points = std::move(mesh.points);
  d.triangles = std::move(mesh.triangles);
  d.what = fmt::format("{} ('{}')", name, array);
  return d;
}

ScalarMeshData load_scalar_mesh(const std::filesystem::path& file, const std::string& array) {
  const std::string ext = lower_extension(file);
  if (ext != ".vtu" && ext != ".msh") {
    throw InputError(
        fmt::format("{}: data for a Hessian metric must be on a .vtu or .msh mesh (got '{}')", file.string(), ext));
  }
  MeshPointData pd;
  pd.wanted = array;
  MeshReadReport report;
  SurfaceCells cells;
  Mesh mesh = with_quads_split(
      ext == ".vtu" ? read_vtu(file, report, &pd, &cells) : read_msh(file, report, &pd, &cells), cells);
  const std::string name = file.string();
  if (mesh.triangles.empty())
    throw InputError(
        fmt::format("{}: the mesh has no triangles; data for a Hessian metric needs triangle cells", name));
  if (!pd.array) {
    const std::string has = pd.point_arrays.empty()
                                ? std::string("the file has no point data")
                                : fmt::format("its point-data arrays are: {}", fmt::join(pd.point_arrays, ", "));
    throw InputError(
        fmt::format("{}: no point-data array '{}' (the function of the Hessian metric); {}", name, array, has));
  }
  const PointDataArray& a = *pd.array;
  const std::size_t n = mesh.points.size();
  if (a.components != 1 || a.values.size() != n) {
    throw InputError(
        fmt::format("{}: point-data array '{}' has {} components; the function must be a scalar (1 component)", a.where,
                    array, a.components));
  }
  std::vector<char> used(n, 0);
  for (const auto& t : mesh.triangles)
    for (int v : t) used[static_cast<std::size_t>(v)] = 1;
  for (std::size_t i = 0; i < n; ++i) {
    if (!used[i]) continue;
    const Vec2 p = mesh.points[i];
    const std::string label =
        i < pd.point_ids.size() ? fmt::format("node {}", pd.point_ids[i]) : fmt::format("point {}", i);
    if (!a.given.empty() && !a.given[i])
      throw InputError(fmt::format("{}: '{}' has no value for {} ({}, {}), a vertex of a triangle", a.where, array,
                                   label, p.x, p.y));
    if (!std::isfinite(a.values[i]))
      throw InputError(fmt::format("{}: '{}' at {} ({}, {}) is {}, not a finite number", a.where, array, label, p.x,
                                   p.y, a.values[i]));
  }
  ScalarMeshData d;
  d.points = std::move(mesh.points);
  d.triangles = std::move(mesh.triangles);
  d.values = a.values;
  d.what = fmt::format("{} ('{}')", name, array);
  return d;
}

std::unique_ptr<MeshMetricField> make_mesh_metric_field(MetricMeshData data) {
  return std::make_unique<MeshMetricField>(std::move(data.points), std::move(data.triangles), std::move(data.metrics),
                                           std::move(data.what));
}

}  // namespace pdmesh
