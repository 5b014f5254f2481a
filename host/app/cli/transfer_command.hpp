// `pdmesh transfer FROM TO --out X.vtu` (docs/motion.md, "Solution transfer"): the point data of mesh
// FROM interpolated linearly at the points of mesh TO (mesh/transfer.hpp), written with TO as a .vtu.
#pragma once
#include <string>
#include <vector>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"
#include "mesh/transfer.hpp"

namespace pdmesh {

// The point arrays `arrays` of FROM (a .vtu or .msh; empty: every point array but kind, q and
// node_id) interpolated at the points of `target` and appended to its point_data: linearly in FROM's
// triangles and in its quads split along their shorter diagonal. Throws InputError (before `target`
// changes) on a missing array (listing FROM's), FROM without point data or without cells. Returns the names transferred
// and FROM's point count; `counts` adds up where the points were found.
struct TransferredArrays {
  std::vector<std::string> names;
  std::size_t source_points = 0;
};
TransferredArrays transfer_point_arrays(const std::string& from, const std::vector<std::string>& arrays, Mesh& target,
                                        TransferCounts& counts);

// `target` with its point data as a .vtu: its triangles, or with `cells`' quads (read_mesh's, a layered
// mesh's) its triangles and quads, as a layered run's mesh.vtu holds them.
std::string transferred_vtu_string(const Mesh& target, const SurfaceCells& cells);

// FROM: a .vtu or .msh with point data; TO: any mesh pdmesh reads; out: a .vtu path. `arrays`: the
// arrays to transfer (empty: every point array but kind, q and node_id). TO's own node_id (a motion
// step's) is kept. Throws InputError (nothing written) on a missing array, FROM without point data,
// an unreadable mesh or an output that is not .vtu. Returns the exit status.
int run_transfer(const std::string& from, const std::string& to, const std::string& out,
                 const std::vector<std::string>& arrays, bool quiet);

}  // namespace pdmesh
