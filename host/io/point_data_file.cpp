// Meshes with point data (point_data_file.hpp).
#include "io/point_data_file.hpp"

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/msh_reader.hpp"
#include "io/vtu_reader.hpp"

namespace pdmesh {

Mesh read_mesh_with_point_data(const std::filesystem::path& path, MeshPointData& data, SurfaceCells* cells) {
  MeshReadReport report;
  const std::string e = lower_extension(path);
  if (e == ".vtu") return read_vtu(path, report, &data, cells);
  if (e == ".msh") return read_msh(path, report, &data, cells);
  throw InputError(fmt::format("{}: point data is read from .vtu or .msh files only", path.string()));
}

std::vector<std::string> point_array_names(const std::string& path) {
  MeshPointData listing;
  (void)read_mesh_with_point_data(path, listing);
  return listing.point_arrays;
}

}  // namespace pdmesh
