// The cleanup in a metric (docs/metric-fields.md, "Cleanup in the metric"): what a metric run does
// to its triangulation in the metric instead of the isotropic cleanup (cleanup.hpp), which works on
// angles. Outer iterations of edge splits (metric length L > √2, a new node at the metric midpoint,
// on its curve for a boundary edge), edge collapses (L < MetricOpsOptions::collapse_below, 0.8),
// flips that raise the smallest metric quality Q, and node smoothing and climbing in the metric,
// until an iteration changes nothing or has settled the mesh (no split or collapse, the smallest Q not
// raised, the mean Q still), eight iterations in a row have not raised the smallest Q, or the
// iteration cap. It works on the isotropic cleanup's EditableMesh and its edits (mesh_edits.cpp),
// scored by a MetricEvaluator; the metric at every node, new or moved, is the field's there.
// Triangles stay strictly counter-clockwise in physical space (exact orient2d); fixed nodes never
// move or go; boundary nodes slide and are inserted or removed only along their own curve.
#pragma once
#include <cstddef>
#include <vector>

#include "cleanup/metric_ops.hpp"
#include "geometry/geometry_tree.hpp"
#include "mesh/mesh.hpp"
#include "nodes/node_set.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

struct MetricCleanupOptions {
  int iterations = 16;         // outer iterations at most (the case's cleanup.iterations)
  bool topology = true;        // splits and collapses (the case's cleanup.topology); off: flips and smoothing
  bool split_boundary = true;  // boundary edges may be split (the case's cleanup.split_boundary)
  int smoothing_sweeps = 3;    // smoothing sweeps per outer iteration, each followed by flips
};

struct MetricCleanupStats {
  cleanup::MetricOpsCounts counts;
  int iterations_run = 0;
  double seconds = 0.0;
};

struct MetricCleanupResult {
  Mesh mesh;                    // original nodes first, in order, less removed ones; new ones after
  NodeSet nodes;                // its nodes, with kinds and the curve chains
  std::vector<Metric> metrics;  // the field's metric at each of mesh.points
  MetricCleanupStats stats;
};

// Cleans `mesh` (the triangulation in the metric of `nodes`) in `metric`. `tree` gives the curves
// boundary nodes slide on; `spacing` the q of new nodes in the node set. Deterministic.
MetricCleanupResult clean_mesh_in_metric(const Mesh& mesh, const NodeSet& nodes, const GeometryTree& tree,
                                         const SpacingField& spacing, const MetricField& metric,
                                         const MetricCleanupOptions& options);

}  // namespace pdmesh
