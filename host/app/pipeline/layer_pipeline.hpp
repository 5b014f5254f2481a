// `pdmesh mesh` with [[boundary_layer]] (docs/boundary-layers.md): after stage spacing the layers are
// grown from the wall curves (the case's field as the core spacing they stop at), and the particle
// core is the case again on the layer fronts: the fronts as curves whose every point is a fixed node,
// and the case's field lowered near the fronts to growth x the last layer's height (graded). After
// the core's stage mesh, the layer cells and the core triangles are one mesh (mixed cells or all
// triangles) in the mesh files, the table and quality.json gain the layer measures. Under a metric
// field the wall curves are reduced to points about one metric unit apart, the layers stop at the
// metric's size along their rays, the core's metric is the case's graded down to the layers' last
// heights at the fronts, and the core and the fronts are measured in the metric
// (docs/boundary-layers.md, "Under a metric field").
#pragma once
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/layer_metric.hpp"
#include "app/pipeline/layer_periodic.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/run_phases.hpp"
#include "io/mixed_mesh.hpp"
#include "layers/boundary_layers.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// One [[boundary_layer]] table, built.
struct LayerSection {
  CaseConfig::BoundaryLayer config;
  LayerSettings settings;
  std::shared_ptr<const Geometry> geometry;  // what it was built on: the input, with earlier sections' fronts
  std::vector<int> walls;                    // its wall curves in `geometry`
  LayerMesh mesh;
};

struct LayeredCase {
  std::vector<LayerSection> sections;
  CaseConfig core;  // the core's case: the front curves, their field, no [[boundary_layer]]
  // Under a metric field: each ray's top, direction and growth x its last layer, from which the
  // core's metric is graded (FrontGradedMetric, layered_core_inputs), at the core's gradation.
  std::vector<FrontMetricSource> front_metric;
  double gradation = 0.2;
  double seconds = 0.0;
  // The core's curves that are layer fronts (the core's other curves of fixed points are periodic).
  std::set<std::string> fronts;
  // With [[periodic]]: the tables' transforms, and the layers' end columns on periodic curves.
  std::vector<PeriodicTable> periodic;
  std::vector<PeriodicColumn> periodic_columns;
  bool is_front(const Curve& c) const { return fronts.count(c.name) > 0; }
};

// InputError (before anything is written) for an unknown curve name, settings the generator refuses, or an output
// format that cannot hold the layer cells (msh22, triangle), and for --resume. With [[periodic]]: a wall chain that
// ends on a periodic curve must end on its image too, in the same table; the two end columns are tied and the image's
// made the exact transform of the source's (InputError where the walls are not periodic there), and the core's case
// keeps the tables with the transforms resolved on the input. Keeps a reference to `spacing`'s field in the core's
// case: it must outlive it.
std::unique_ptr<LayeredCase> build_layers(const CaseConfig& config, const MeshInputs& inputs,
                                          const SpacingStage& spacing);

// The core's inputs: layered.core's, and under a metric field (`inputs.metric`, the case's) the case's
// metric graded down to the layers at their fronts (FrontGradedMetric over inputs.metric, which must
// outlive them) instead of the metric the core's case would build. The projection is the caller's to set.
std::unique_ptr<MeshInputs> layered_core_inputs(const LayeredCase& layered, const MeshInputs& inputs);

// The core's nodes without the Boundary nodes on a curve of fixed points: interior nodes that the simulation
// snapped onto a front curve (its points are the layer's nodes; one between them would hang on a layer cell's
// edge) or, with [[periodic]], onto a periodic curve (it would have no partner).
NodeSet without_front_nodes(const NodeSet& nodes, const Geometry& core_geometry, std::size_t& dropped);

// A layer top whose core cell above reaches more than this many last layers up its ray gets a pinned
// first-row node (steep_junctions, place_first_row).
inline constexpr double kSteepJunction = 1.45;

// The front nodes whose core cell above continues the layer too steeply: the core neighbour most in
// line with the ray (within acos 0.7) lies more than `limit` last layers up the ray.
std::vector<Vec2> steep_junctions(const LayeredCase& layered, const Mesh& core, double limit);

// The core's first row on the layers' rays, for the front nodes in `only` (all where null): for
// each, the interior node nearest to the point growth x its last layer beyond it along its ray
// (within 1.25 of that step) is moved there and made Fixed, so that the cleanup leaves it: the
// core's cell above the top then continues the layer's growth whatever the initial fill left there.
// Where the front's edges at the top are longer than 1.2 steps the point is lifted (up to 1.2
// steps) and above 1.5 steps there is none; none within 0.6 steps of another front node or of a
// point already taken; each node moves at most once. Returns how many moved.
std::size_t place_first_row(NodeSet& nodes, const LayeredCase& layered, const std::vector<Vec2>* only = nullptr);

// The core's cleaned mesh of the simulated `nodes` (config: the core's case, nothing written):
// without the nodes snapped onto a front, and where the cleanup is on, meshed again with a pinned
// first-row node at each steep junction (more than 1.45 last layers). `triangulated`: the
// simulation's final mesh of `nodes`, or null.
Mesh mesh_layered_core(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
                       const NodeSet& nodes, const LayeredCase& layered, RunPhases* phases = nullptr,
                       const Mesh* triangulated = nullptr);

// The layer cells and the core mesh as one mesh: the core's points first, each front node of the
// layers mapped onto the core's point at exactly its place (the Python API's layered mesh).
MixedMesh merged_layer_mesh(const MeshInputs& inputs, const LayeredCase& layered, const MeshInputs& core_inputs,
                            const Mesh& core_mesh);

// The layer cells and the core mesh (the cleaned triangles of layered.core's nodes) as one mesh:
// the mesh files, the pictures, the table and quality.json (with the layer measures).
void write_layered_outputs(const CaseConfig& config, const MeshInputs& inputs, const LayeredCase& layered,
                           const MeshInputs& core_inputs, const Mesh& core_mesh, RunPhases& phases);

}  // namespace pdmesh
