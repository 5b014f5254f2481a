// `pdmesh adapt DOMAIN --solution SOL --array NAME --complexity C --out DIR` (docs/cli.md, "pdmesh adapt"):
// one step of the solve-adapt loop. The case of DOMAIN (resolved as pdmesh mesh and pdmesh smooth
// resolve their input) has its [spacing] replaced by the Hessian metric of SOL's point arrays, the
// `spacing.field = "hessian"` keys (docs/metric-fields.md), and is meshed by run_mesh; then SOL's point
// arrays are interpolated onto the new mesh's points (pdmesh transfer's code) as DIR/solution.vtu.
#pragma once
#include "app/config/adapt_keys.hpp"
#include "app/config/case_file.hpp"
#include "app/pipeline/solution_transfer.hpp"

namespace pdmesh {

// The command on a case built with adapt_overrides: checks, before anything is written, that SOL has
// every array (InputError listing those it has), that the run writes a mesh file solution.vtu can
// follow (unless --no-transfer) and that solution.vtu is not SOL; then run_mesh; then, when the run
// succeeded, SOL's point arrays (all but kind, q and node_id) interpolated onto the written mesh's
// points, written atomically as DIR/solution.vtu (write_adapted_solution). Returns the exit status.
int run_adapt(const CaseConfig& config, const AdaptOptions& options);

}  // namespace pdmesh
