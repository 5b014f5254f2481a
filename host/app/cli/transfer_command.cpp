// The transfer command (transfer_command.hpp).
#include "app/cli/transfer_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mesh_formats.hpp"
#include "io/vtu_reader.hpp"

namespace pdmesh {

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
