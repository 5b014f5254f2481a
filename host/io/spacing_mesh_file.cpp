// Reading a spacing background mesh: .vtu or .msh by extension, through the mesh readers.
#include "io/spacing_mesh_file.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mixed_mesh.hpp"
#include "io/msh_reader.hpp"
#include "io/vtu_reader.hpp"

namespace pdmesh {

std::unique_ptr<MeshSpacing> load_mesh_spacing(const std::filesystem::path& file, const std::string& array) {
  const std::string ext = lower_extension(file);
  if (ext != ".vtu" && ext != ".msh") {
    throw InputError(
        fmt::format("{}: a spacing background mesh must be a .vtu or .msh file (got '{}')", file.string(), ext));
  }
  MeshPointData pd;
  pd.wanted = array;
  MeshReadReport report;
  SurfaceCells cells;
  Mesh mesh = with_quads_split(
      ext == ".vtu" ? read_vtu(file, report, &pd, &cells) : read_msh(file, report, &pd, &cells), cells);
  MeshFieldData d;
  d.file = file.string();
  d.array = array;
  if (mesh.triangles.empty()) {
    throw InputError(fmt::format(
        "{}: the mesh has no triangles{}; a spacing background mesh needs triangle cells", d.file,
        report.skipped_elements > 0 ? fmt::format(" (it has {} other cells)", report.skipped_elements) : ""));
  }
  if (!pd.array) {
    const std::string has = pd.point_arrays.empty()
                                ? std::string("the file has no point data")
                                : fmt::format("its point-data arrays are: {}", fmt::join(pd.point_arrays, ", "));
    const std::string other =
        pd.other_arrays.empty() ? std::string() : fmt::format(" (other data: {})", fmt::join(pd.other_arrays, ", "));
    throw InputError(fmt::format("{}: no point-data array '{}' (spacing.array); {}{}", d.file, array, has, other));
  }
  if (pd.array->components != 1) {
    throw InputError(
        fmt::format("{}: point-data array '{}' has {} components; the spacing must be a scalar (1 component)",
                    pd.array->where, array, pd.array->components));
  }
  d.points = std::move(mesh.points);
  d.triangles = std::move(mesh.triangles);
  d.q = std::move(pd.array->values);
  d.given = std::move(pd.array->given);
  d.array_where = pd.array->where;
  d.point_ids = std::move(pd.point_ids);
  return std::make_unique<MeshSpacing>(std::move(d));
}

}  // namespace pdmesh
