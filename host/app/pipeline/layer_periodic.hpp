// [[periodic]] together with [[boundary_layer]] (docs/geometry-input.md, "Periodic curves"): a wall
// chain that ends on a periodic curve ends on its image too; the two end rays are tied (the same
// layers), the image's end column is the exact transform of the source's, and the merged mesh pairs
// the column's nodes as well as the core's.
#pragma once
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/periodic_pipeline.hpp"
#include "io/mixed_mesh.hpp"
#include "layers/boundary_layers.hpp"
#include "mesh/periodic_links.hpp"

namespace pdmesh {

// One [[periodic]] table as the layer tables see it: its curves' names and its transform (resolved
// on the input geometry once, so that every table and the core use the same one).
struct PeriodicTable {
  const CaseConfig::Periodic* config = nullptr;
  PeriodicTransform transform;
  double tolerance = 0.0;  // 1e-6 of the geometry's diagonal
};

// The open chain ends of one [[boundary_layer]] table on periodic curves: per tie the wall node on
// the source curve (a), the one on the image (b), and its [[periodic]] table.
struct PeriodicLayerEnds {
  std::vector<TiedEnds> tied;
  std::vector<const PeriodicTable*> table;
};

// The ends of `walls` (curve indices of `geometry`, one [[boundary_layer]] table `b`) on the tables'
// periodic curves. InputError (naming the case file, both tables, the curves and the points) where
// the walls end on one curve of a pair and not at the transformed point of the other, e.g. a wall
// whose continuation on the image side is in another [[boundary_layer]] table or none.
PeriodicLayerEnds periodic_layer_ends(const std::vector<PeriodicTable>& tables, const Geometry& geometry,
                                      const std::vector<int>& walls, const CaseConfig::BoundaryLayer& b);

// A layer's end column on a periodic curve and its image's: the nodes from the wall node up to the
// top (the image's its transforms, but for its own wall node).
struct PeriodicColumn {
  std::string source, image;  // the curves
  std::vector<Vec2> source_nodes, image_nodes;
};

// After build_boundary_layers with ends.tied: each image end column made the exact transform of its
// source's (the wall nodes stay). InputError naming the walls, the curves and the angles where the
// walls are not periodic (the built image column is farther than the table's tolerance from the
// transformed source column). Returns the pairs of the columns that run along their curves.
std::vector<PeriodicColumn> match_periodic_columns(LayerMesh& layers, const Geometry& geometry,
                                                   const PeriodicLayerEnds& ends, const CaseConfig::BoundaryLayer& b);

// The periodic pairs of the merged mesh in its curve indices: the core's pairs (core_inputs.periodic,
// whose periodic curves start at the layers' tops) with the layer columns' nodes below the tops.
std::vector<PeriodicNodes> merged_periodic_pairs(const MixedMesh& merged, const std::vector<PeriodicColumn>& columns,
                                                 const MeshInputs& core_inputs);

}  // namespace pdmesh
