// The solution carried from one mesh to another as the commands write it (docs/motion.md, "Solution
// transfer"; docs/cli.md, "pdmesh adapt"): a .vtu or .msh file's point arrays interpolated at a
// mesh's points (mesh/transfer), the .vtu that holds them, and pdmesh adapt's solution.vtu on the mesh
// file its run wrote. pdmesh transfer, pdmesh adapt and the Python binding share it.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"
#include "mesh/transfer.hpp"

namespace pdmesh {

// The point arrays `arrays` of FROM (a .vtu or .msh; empty: every point array but kind, q and
// node_id) interpolated at the points of `target` and appended to its point_data: linearly in FROM's
// triangles and in its quads split along their shorter diagonal. Throws InputError (before `target`
// changes) on a missing array (listing FROM's), FROM without point data or without cells. Returns the
// names transferred and FROM's point count; `counts` adds up where the points were found.
struct TransferredArrays {
  std::vector<std::string> names;
  std::size_t source_points = 0;
};
TransferredArrays transfer_point_arrays(const std::string& from, const std::vector<std::string>& arrays, Mesh& target,
                                        TransferCounts& counts);

// `target` with its point data as a .vtu: its triangles, or with `cells`' quads (read_mesh's, a layered
// mesh's) its triangles and quads, as a layered run's mesh.vtu holds them.
std::string transferred_vtu_string(const Mesh& target, const SurfaceCells& cells);

// The file solution.vtu in `config`'s output directory.
std::filesystem::path adapted_solution_path(const CaseConfig& config);

// The first mesh file of `config`'s output.formats that pdmesh reads back (mesh_format_is_read), in its
// output directory: the mesh pdmesh adapt makes solution.vtu on; nullopt when the run writes none.
std::optional<std::filesystem::path> adapted_mesh_file(const CaseConfig& config);

// pdmesh adapt's last step, after the run: `mesh_file` (adapted_mesh_file, written by the run) read
// back, `solution`'s point arrays (all but kind, q and node_id) interpolated at its points
// (transfer_point_arrays), written atomically as adapted_solution_path(config). `target` is the mesh
// read back with those arrays as its point_data.
struct AdaptedSolution {
  Mesh target;
  TransferredArrays moved;
  TransferCounts counts;
};
AdaptedSolution write_adapted_solution(const CaseConfig& config, const std::string& solution,
                                       const std::filesystem::path& mesh_file);

}  // namespace pdmesh
