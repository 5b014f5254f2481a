// [[periodic]] (docs/geometry-input.md, "Periodic curves"): the source curve's boundary nodes are
// placed by the case's field (the smaller of q at a point and at its image), the image curve gets
// their transforms, and the later stages run on a case whose two curves are `fixed_points` polylines
// of those nodes, so that nothing moves, removes or adds a node on them.
#pragma once
#include <memory>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "mesh/periodic_links.hpp"

namespace pdmesh {

struct PeriodicCase {
  CaseConfig core;                   // the case on the fixed-node curves, its field the case's
  std::vector<PeriodicNodes> pairs;  // per [[periodic]] table, in the core's curve indices
  std::vector<std::string> notes;    // one line per table for the progress output
};

// Checks the tables against the geometry and the case (InputError naming the case file, the table
// and the values, before anything is written): unknown or constraint curves, a transform that does
// not map the source onto the image within 1e-6 of the geometry's diagonal (the largest distance and
// where), a periodic curve that is a [[boundary_layer]] wall, [motion], --resume, a warm start. Under
// a metric field the source's stations are unit metric lengths apart (the shorter step of a point
// and its image) and the core runs in the case's metric.
// With layers it runs on the layered core's case and inputs (build_layers has tied the layers' end
// columns on the periodic curves). Keeps a reference to `spacing`'s field in the core's case: it must
// outlive it.
std::unique_ptr<PeriodicCase> build_periodic(const CaseConfig& config, const MeshInputs& inputs,
                                             const SpacingStage& spacing);

// One [[periodic]] table resolved against a geometry: its curves' indices there and its transform
// (InputError naming the case file, the table and the values where the curves are unknown, embedded
// constraints, or not mapped onto each other within 1e-6 of the geometry's diagonal).
struct ResolvedPeriodic {
  int source = 0, image = 0;
  PeriodicTransform transform;
  double miss = 0.0;       // the largest distance of T(source) from the image
  double tolerance = 0.0;  // 1e-6 of the geometry's diagonal
};
ResolvedPeriodic resolve_periodic(const CaseConfig::Periodic& table, const Geometry& on);

// The core's inputs: MeshInputs of periodic.core, with the case's regions, projection, pairs and
// metric (by reference: `inputs` must outlive them).
std::unique_ptr<MeshInputs> periodic_core_inputs(const PeriodicCase& periodic, const MeshInputs& inputs);

// The refusals of build_periodic that need no geometry (also for runs that do not reach it: motion).
void check_periodic_case(const CaseConfig& config);
// Every refusal of build_periodic, right after reading (before the progress lines and the spacing).
void check_periodic(const CaseConfig& config, const MeshInputs& inputs);

}  // namespace pdmesh
