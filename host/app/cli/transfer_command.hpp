// `pdmesh transfer FROM TO --out X.vtu` (docs/motion.md, "Solution transfer"): the point data of mesh
// FROM interpolated linearly at the points of mesh TO (mesh/transfer.hpp), written with TO as a .vtu.
#pragma once
#include <string>
#include <vector>

#include "app/pipeline/solution_transfer.hpp"

namespace pdmesh {

// FROM: a .vtu or .msh with point data; TO: any mesh pdmesh reads; out: a .vtu path. `arrays`: the
// arrays to transfer (empty: every point array but kind, q and node_id). TO's own node_id (a motion
// step's) is kept. Throws InputError (nothing written) on a missing array, FROM without point data,
// an unreadable mesh or an output that is not .vtu. Returns the exit status.
int run_transfer(const std::string& from, const std::string& to, const std::string& out,
                 const std::vector<std::string>& arrays, bool quiet);

}  // namespace pdmesh
