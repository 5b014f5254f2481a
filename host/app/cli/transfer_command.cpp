// The transfer command (transfer_command.hpp).
#include "app/cli/transfer_command.hpp"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "io/point_data_file.hpp"
#include "io/vtu_reader.hpp"
#include "io/vtu_writer.hpp"
#include "mesh/transfer.hpp"

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
  MeshPointData listing;
  const Mesh source = read_source(from, listing);
  std::vector<std::string> names = arrays;
  if (names.empty()) {
    for (const std::string& n : listing.point_arrays)
      if (n != "kind" && n != "q" && n != "node_id") names.push_back(n);
    if (names.empty())
      throw InputError(fmt::format(
          "{}: no point data to transfer (point arrays: {})", from,
          listing.point_arrays.empty() ? "none" : fmt::format("{}", fmt::join(listing.point_arrays, ", "))));
  }
  for (const std::string& n : names)
    if (std::find(listing.point_arrays.begin(), listing.point_arrays.end(), n) == listing.point_arrays.end())
      throw InputError(
          fmt::format("{}: no point array '{}' (point arrays: {})", from, n, fmt::join(listing.point_arrays, ", ")));
  if (source.triangles.empty()) throw InputError(fmt::format("{}: the mesh has no cells", from));
  std::vector<PointValues> values;
  for (const std::string& n : names) {
    MeshPointData data;
    data.wanted = n;
    (void)read_mesh_with_point_data(from, data);
    const PointDataArray& a = *data.array;
    values.push_back(
        {n, a.components, transfer_point_values(source, a.values, a.components, target.points, &counts), false});
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

int run_transfer(const std::string& from, const std::string& to, const std::string& out,
                 const std::vector<std::string>& arrays, bool quiet) {
  if (lower_extension(out) != ".vtu") throw InputError(fmt::format("--out {}: the output must be a .vtu file", out));
  MeshReadReport report;
  SurfaceCells cells;
  Mesh target = read_mesh(to, report, &cells);
  // A motion step's own ids stay with its points.
  if (lower_extension(to) == ".vtu") {
    MeshPointData ids;
    ids.wanted = "node_id";
    (void)read_vtu(to, report, &ids);
    if (ids.array && ids.array->components == 1) target.point_data.push_back({"node_id", 1, ids.array->values, true});
  }
  TransferCounts counts;
  const TransferredArrays moved = transfer_point_arrays(from, arrays, target, counts);
  write_file_atomically(out, transferred_vtu_string(target, cells));
  if (!quiet)
    fmt::print(stderr,
               "transfer: {} ({}) from {} ({} points) onto {} ({} points): {} points in a triangle, {} outside the "
               "mesh (nearest triangle, at most {:.3g} away); wrote {}\n",
               fmt::join(moved.names, ", "), moved.names.size(), from, moved.source_points, to, target.points.size(),
               counts.inside, counts.outside, counts.max_distance, out);
  return 0;
}

}  // namespace pdmesh
