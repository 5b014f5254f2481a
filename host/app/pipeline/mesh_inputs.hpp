// The first stages of `pdmesh mesh` (mesh_pipeline.hpp lists them all): read (MeshInputs), spacing
// (SpacingStage, then the node and memory limits) and initial (the boundary placement and the fill).
// Each is a value built from the ones before it; none changes them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry/heal.hpp"
#include "geometry/projection.hpp"
#include "geometry/smooth_curve.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/periodic_links.hpp"
#include "nodes/node_set.hpp"
#include "spacing/background_field.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"
#include "spacing/spacing_pipeline.hpp"

namespace pdmesh {

// spacing.relax_scale where it applies (an isotropic run), else 1.
double relax_scale(const CaseConfig& config);
// The case's spacing keys as pipeline options (boundary nodes are the input points: the sources
// keep to kInputBoundaryFloor of the input segments next to them, docs/spacing.md); the scale is
// spacing.scale x relax_scale(config).
SpacingOptions spacing_options(const CaseConfig& config);

// Stage read: the geometry, its tree and the base spacing field; throws LimitError for coordinates
// too large to resolve at the segment lengths or the spacing (check_coordinate_resolution). Not
// movable: the tree and the boundary spacing field refer to the geometry.
//
// Two geometries (docs/geometry-input.md, "Smooth curves"): `geometry` is the input as read; its
// segments define the spacing field (eq. 3.6's l_s; a dense polyline would shrink q). The node
// geometry is the curve the nodes live on: with geometry.curves = "smooth", the dense polyline of
// the smooth curves (same curves, loops and critical points); with "polyline", `geometry` itself.
// Everything but the spacing field uses the node geometry: boundary nodes, the node-count estimate
// and the fill, sliding and snapping, inside tests, the mesh check's area and the pictures.
struct MeshInputs {
  explicit MeshInputs(const CaseConfig& config);
  MeshInputs(const MeshInputs&) = delete;
  MeshInputs& operator=(const MeshInputs&) = delete;

  Geometry geometry;  // the input geometry (spacing field), healed with geometry.heal
  // What healing changed (geometry.heal; empty when off or nothing changed), and the curves as read
  // when it changed something (healing.png draws them).
  HealResult healing;
  std::vector<std::vector<Vec2>> heal_input;
  std::unique_ptr<GeometryTree> tree;  // over `geometry`
  // spacing.field "metric" or "hessian": the metric field (spacing/metric_field.hpp); null for the
  // isotropic fields. `spacing` is then its isotropic size sqrt(h1 h2) (MetricSizeField).
  std::unique_ptr<MetricField> metric;
  std::unique_ptr<SpacingField> spacing;  // the base field (eq. 3.6, an expression, data), exact
  SpacingOptions spacing_options;
  // One line about a spacing field read from a file (spacing.field = "mesh"); empty otherwise.
  std::string spacing_summary;
  std::unique_ptr<DenseGeometry> dense;      // smooth curves; null for "polyline" (or after a fallback)
  std::unique_ptr<GeometryTree> dense_tree;  // over dense->geometry
  BoundaryNodeRule boundary_rule = BoundaryNodeRule::Input;
  // Why geometry.curves = "smooth" fell back to the polylines (the smooth curves intersect); empty
  // when it did not.
  std::string smooth_fallback;
  // What a refusal by --max-nodes appends: where eq. 3.6's q comes from (empty unless the field is
  // eq. 3.6 of the input segments).
  std::string node_hint;
  // geometry.projection = "equirectangular": the projection the geometry was read through; the mesh
  // and node files map their coordinates back with it (app/pipeline/mesh_outputs.cpp).
  std::optional<Equirectangular> projection;
  // [[periodic]]: per table the nodes of its two curves (set on the core's inputs by
  // periodic_core_inputs; empty otherwise). The mesh stage finds them among the mesh's points.
  std::vector<PeriodicNodes> periodic;

  const Geometry& node_geometry() const { return dense ? dense->geometry : geometry; }
  const GeometryTree& node_tree() const { return dense ? *dense_tree : *tree; }
  std::vector<std::string> curve_names() const;
};

// Stage spacing: the final spacing field (the pipeline over the inputs' base field), which the
// initialization, boundary placement, quality and pictures read (field()), and its quadtree, which
// both simulation backends and the node estimate sample (background()). A LimitError of its budgets
// (--max-nodes, --max-memory) names the case. Refers to `inputs`, which must outlive it.
class SpacingStage {
 public:
  // Meshing: the quadtree is built here too (in the thesis' case eq. 3.6's lookup table, which the
  // pipeline builds only on demand). FieldOnly: for readers of field() alone (pdmesh quality), which
  // then leave the thesis' quadtree unbuilt.
  enum class Build { Meshing, FieldOnly };
  SpacingStage(const CaseConfig& config, const MeshInputs& inputs, Build build = Build::Meshing);
  SpacingStage(const SpacingStage&) = delete;
  SpacingStage& operator=(const SpacingStage&) = delete;

  const SpacingPipeline& pipeline() const { return *pipeline_; }
  const SpacingField& field() const { return pipeline_->field(); }
  // The field as the case asks for it: field() / spacing.relax_scale (field() itself where that is 1),
  // which the quality's spacing conformance, the mesh's point data q and spacing.png report.
  const SpacingField& asked() const { return asked_ ? *asked_ : field(); }
  // What field() is of asked(): spacing.relax_scale.
  double relax_scale() const { return relax_scale_; }
  // The metric field of a metric run (MeshInputs::metric), null for an isotropic one. The nodes are
  // placed by field(), its isotropic size; the triangulation and the measures use the metric.
  const MetricField* metric() const { return metric_; }
  // The quadtree (built by the constructor unless FieldOnly; then by the first call, not thread-safe).
  const BackgroundSpacing& background() const;

 private:
  std::string source_;     // the case file, for messages
  std::string node_hint_;  // MeshInputs::node_hint
  std::unique_ptr<SpacingPipeline> pipeline_;
  double relax_scale_ = 1.0;
  std::unique_ptr<SpacingField> asked_;  // field() / relax_scale_, when that is not 1
  const MetricField* metric_ = nullptr;
};

// Stage spacing, its limits: refuses, with LimitError naming the numbers, a case whose
// hexagonal-packing estimate (or requested total) exceeds config.max_nodes. Returns the estimate of the
// final field. When the pipeline modifies the base field, the base field's quadtree has been checked
// first, inside SpacingStage (the sources only lower q), so that an absurd case is refused before the
// limits refine it further. It then refuses, with LimitError, a run whose later stages would need
// more than config.max_memory (run_memory_bytes).
double check_node_limit(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing);

// The memory model of a run's stages after the spacing field (docs/robustness.md, "Memory"): what a
// run holds per node at its peak (the node set and initialization tree, the simulation's arrays and
// neighbour grid, an OpenCL CPU device's buffers, which are host memory, the triangulation and the
// cleanup's editable mesh, the writers' text), plus the process's base (the libraries, PoCL's worker
// arenas, the pictures' bands) and the field. kRunBytesBase + kRunBytesPerNode x kRunNodeGrowth
// per estimated node bounds the peaks measured on the annulus cases and the unit square
// (docs/robustness.md, "Memory") and keeps a 20M-node annulus within a 24 GB machine's default
// --max-memory.
inline constexpr double kRunBytesBase = 256.0 * 1024 * 1024;
inline constexpr double kRunBytesPerNode = 768.0;
// Population control inserts nodes where the estimate is low: a few percent on the corpus, 26 % on
// the annulus benchmark cases (their estimate is of the initial fill's field).
inline constexpr double kRunNodeGrowth = 1.25;
double run_memory_bytes(double nodes, std::size_t field_bytes);

// Stage initial, its first part: the boundary nodes on the node geometry (boundary.nodes = "spacing",
// or the input points of smooth curves), placed by the final field, and what the initialization tree
// refines to along each node-geometry segment (InitTreeOptions::segment_resolution: the boundary-node
// spacing there, from the same placement). Both empty for the thesis' rule, which
// make_initial_distribution applies itself. LimitError when the field asks for more than
// config.max_nodes boundary nodes.
struct BoundaryPlacement {
  std::optional<NodeSet> nodes;
  std::vector<double> resolution;
};
BoundaryPlacement place_boundary(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing);

// Stage initial of a metric run: boundary stations at unit metric length along each curve
// (CurveMetricSpacing), then the interior fill in the metric (init/metric_fill.hpp). make_initial
// calls it when inputs.metric is set.
InitialDistribution make_metric_initial(const CaseConfig& config, const MeshInputs& inputs,
                                        const SpacingStage& spacing);

// Stage initial: the initial distribution (the boundary placement, then the tree fill).
InitialDistribution make_initial(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing);

}  // namespace pdmesh
