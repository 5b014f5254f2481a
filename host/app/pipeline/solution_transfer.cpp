// Solution transfer as the commands write it (solution_transfer.hpp).
#include "app/pipeline/solution_transfer.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "io/point_data_file.hpp"
#include "io/vtu_writer.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

namespace {

// The source's cells as triangles: a layered mesh's quads split (with_quads_split), so that a point
// inside a quad is interpolated there, not taken from the nearest triangle.
Mesh read_source(const fs::path& path, MeshPointData& data) {
  SurfaceCells cells;
  Mesh mesh = read_mesh_with_point_data(path, data, &cells);
  return with_quads_split(std::move(mesh), cells);
}

}  // namespace

TransferredArrays transfer_point_arrays(const std::string& from, const std::vector<std::string>& arrays, Mesh& target,
                                        TransferCounts& counts) {
  // One read decodes every array asked for; with none named, all of them, the excluded ones dropped below.
  MeshPointData data;
  data.decode = arrays;
  data.decode_all = arrays.empty();
  const Mesh source = read_source(from, data);
  std::vector<std::string> names = arrays;
  if (names.empty()) {
    for (const std::string& n : data.point_arrays)
      if (n != "kind" && n != "q" && n != "node_id") names.push_back(n);
    if (names.empty())
      throw InputError(
          fmt::format("{}: no point data to transfer (point arrays: {})", from,
                      data.point_arrays.empty() ? "none" : fmt::format("{}", fmt::join(data.point_arrays, ", "))));
  }
  for (const std::string& n : names)
    if (std::find(data.point_arrays.begin(), data.point_arrays.end(), n) == data.point_arrays.end())
      throw InputError(
          fmt::format("{}: no point array '{}' (point arrays: {})", from, n, fmt::join(data.point_arrays, ", ")));
  if (source.triangles.empty()) throw InputError(fmt::format("{}: the mesh has no cells", from));
  std::vector<PointValues> values;
  for (const std::string& n : names) {
    const auto a =
        std::find_if(data.arrays.begin(), data.arrays.end(), [&n](const PointDataArray& d) { return d.name == n; });
    values.push_back(
        {n, a->components, transfer_point_values(source, a->values, a->components, target.points, &counts), false});
  }
  for (PointValues& v : values) target.point_data.push_back(std::move(v));
  return {names, source.points.size()};
}

std::string transferred_vtu_string(const Mesh& target, const SurfaceCells& cells) {
  if (cells.quads.empty()) return vtu_string(target);
  MixedMesh mixed = mixed_mesh_of(target, cells);
  mixed.point_data = target.point_data;
  return mixed_vtu_string(mixed);
}

std::optional<fs::path> adapted_mesh_file(const CaseConfig& config) {
  for (const std::string& f : config.output.formats) {
    if (!mesh_format_is_read(f)) continue;
    const auto& ext = mesh_format_extensions(f);
    return config.out_dir / ("mesh" + (f == "triangle" ? std::string(".ele") : ext.front()));
  }
  return std::nullopt;
}

fs::path adapted_solution_path(const CaseConfig& config) { return config.out_dir / "solution.vtu"; }

AdaptedSolution write_adapted_solution(const CaseConfig& config, const std::string& solution,
                                       const fs::path& mesh_file) {
  AdaptedSolution a;
  MeshReadReport report;
  SurfaceCells cells;
  a.target = read_mesh(mesh_file, report, &cells);
  a.target.point_data.clear();
  a.moved = transfer_point_arrays(solution, {}, a.target, a.counts);
  write_file_atomically(adapted_solution_path(config), transferred_vtu_string(a.target, cells));
  return a;
}

}  // namespace pdmesh
