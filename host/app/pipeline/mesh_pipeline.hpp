// `pdmesh mesh`: the pipeline for one validated case, in stages that each finish before the next
// begins, so that nothing is written until every input has been read and checked.
#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <optional>

#include "app/pipeline/backend_choice.hpp"
#include "app/config/case_file.hpp"
#include "app/pipeline/run_phases.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry/smooth_curve.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/mesh.hpp"
#include "sim/simulation.hpp"
#include "spacing/spacing_field.hpp"
#include "spacing/spacing_pipeline.hpp"

namespace pdmesh {

// The case's spacing keys as pipeline options (boundary nodes are the input points: the sources
// keep to kInputBoundaryFloor of the input segments next to them, docs/spacing.md).
SpacingOptions spacing_options(const CaseConfig& config);

// Stage 1: the geometry, its tree and the spacing field; throws LimitError for coordinates too
// large to resolve at the segment lengths or the spacing (check_coordinate_resolution). Not
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

  Geometry geometry;                   // the input geometry (spacing field)
  std::unique_ptr<GeometryTree> tree;  // over `geometry`
  std::unique_ptr<SpacingField> spacing;  // the base field (eq. 3.6, an expression, data), exact
  SpacingOptions spacing_options;
  // The spacing pipeline, built on first use (then also the resolution check of the final field):
  // field() is what the initialization, boundary placement, quality and pictures read,
  // pipeline().background() what both simulation backends sample. Built once; not thread-safe on the
  // first call.
  const SpacingPipeline& pipeline() const;
  const SpacingField& field() const { return pipeline().field(); }
  // pipeline().background(), with the case named in a LimitError of its budgets (--max-nodes,
  // --max-memory) when this call builds it.
  const BackgroundSpacing& background() const;
  // One line about a spacing field read from a file (spacing.field = "mesh"); empty otherwise.
  std::string spacing_summary;
  std::unique_ptr<DenseGeometry> dense;     // smooth curves; null for "polyline" (or after a fallback)
  std::unique_ptr<GeometryTree> dense_tree;  // over dense->geometry
  BoundaryNodeRule boundary_rule = BoundaryNodeRule::Input;
  // Why geometry.curves = "smooth" fell back to the polylines (the smooth curves intersect); empty
  // when it did not.
  std::string smooth_fallback;

  const Geometry& node_geometry() const { return dense ? dense->geometry : geometry; }
  const GeometryTree& node_tree() const { return dense ? *dense_tree : *tree; }
  // The boundary nodes on the node geometry (boundary.nodes = "spacing", or the input points of
  // smooth curves), placed by the spacing field on first use; null for the thesis' rule, which
  // make_initial_distribution applies itself. LimitError when the field asks for more than
  // config.max_nodes of them. Not thread-safe on the first call.
  const NodeSet* boundary_nodes() const;
  // What the initialization tree refines to along each node-geometry segment
  // (InitTreeOptions::segment_resolution: the boundary-node spacing there, from the same placement);
  // null for the thesis' rule (the segment lengths).
  const std::vector<double>* segment_resolution() const;
  std::vector<std::string> curve_names() const;

 private:
  void place_boundary() const;
  mutable std::unique_ptr<SpacingPipeline> pipeline_;
  std::string source_;           // the case file, for messages
  std::uint64_t max_nodes_ = 0;  // the node limit the base field's quadtree and the placement are checked against
  std::string node_hint_;        // appended to a refusal by --max-nodes: where eq. 3.6's q comes from
  mutable bool boundary_placed_ = false;
  mutable std::optional<NodeSet> boundary_;
  mutable std::vector<double> resolution_;
};

// Stage 2: refuses, with LimitError naming the numbers, a case whose hexagonal-packing estimate
// (or requested total) exceeds config.max_nodes. Returns the estimate of the final field. When the
// pipeline modifies the base field, the base field's quadtree is checked first, inside the pipeline
// (the sources only lower q), so that an absurd case is refused before the limits refine it further.
// It then refuses, with LimitError, a run whose later stages would need more than config.max_memory
// (run_memory_bytes).
double check_node_limit(const CaseConfig& config, const MeshInputs& inputs);

// The memory model of a run's stages after the spacing field (docs/robustness.md, "Memory"): what a
// run holds per node at its peak (the node set and initialization tree, the simulation's arrays and
// neighbour grid, an OpenCL CPU device's buffers, which are host memory, the triangulation and the
// cleanup's editable mesh, the writers' text), plus the process's base and the field. Measured on a
// 289k-node estimate (q = 2e-3 on the unit square, 30 iterations, every stage): 1.3 KB per estimated
// node on the host, 1.7 KB with PoCL; 2 KB x 1.25 leaves room for the population's growth.
inline constexpr double kRunBytesBase = 64.0 * 1024 * 1024;
inline constexpr double kRunBytesPerNode = 2048.0;
// Population control inserts nodes where the estimate is low, at most a few percent on the corpus.
inline constexpr double kRunNodeGrowth = 1.25;
double run_memory_bytes(double nodes, std::size_t field_bytes);

// Stage 3: the initial distribution (boundary nodes and the tree fill).
InitialDistribution make_initial(const CaseConfig& config, const MeshInputs& inputs);

// Stage 4: creates config.out_dir; InputError naming it when that fails.
void prepare_output_directory(const CaseConfig& config);

// DIR/spacing.png (and spacing_<view>.png per view): the final field (pipeline().background()).
void write_spacing_picture(const CaseConfig& config, const MeshInputs& inputs);

// The stages below time their phases in `run` and draw their pictures on its background thread;
// what a picture reads (the node sets passed in) must then stay unchanged until
// run->wait_pictures(). Without `run` the pictures are drawn before the stage returns.

// Stage 5: DIR/initial.nodes, and as output.formats asks initial.png and initial_<view>.png per view
// (png), initial.svg (svg), each atomic.
void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs, const InitialDistribution& initial,
                           RunPhases* run = nullptr);

// The simulation settings of the case (iterations, stopping rule, time step, forces, population
// control); the backend, stop flag, background field and resume state are the caller's to add.
SimOptions simulation_options(const CaseConfig& config);

// For callers that drive the stages themselves (the Python API, python/src/): a callback after every
// iteration, on top of the command's own, and the stop flag to poll instead of InterruptGuard::flag().
struct SimulateHooks {
  std::function<void(const HistoryRow&)> on_iteration;
  const std::atomic<bool>* stop = nullptr;
  // The backend when the caller set it up beforehand (run_mesh does, on a thread, while the spacing
  // field is built); it passes its notes to `note`. Empty: simulate() calls choose_backend.
  std::function<ChosenBackend(const std::function<void(const std::string&)>& note)> backend;
  // Non-null: receives the simulation's state as soon as it has ended normally (before its outputs
  // are written), so that a later stop request can checkpoint the finished nodes.
  std::optional<SimState>* finished = nullptr;
};

// Stage 6: the particle dynamics simulation on the chosen backend, updating `nodes` in place, until
// it converges or for simulation.iterations (simulation.stop); writes DIR/history.csv, final.nodes,
// history.png, final.png and final_<view>.png (png), final.svg (svg).
// With `resume`, continues that state (nodes must be its node set). Stops early when core/interrupt's
// flag is set (a signal, or config.stop_after): then writes DIR/checkpoint.pdmesh and nothing else,
// and throws Interrupted naming the iteration and the file. A run stopped by hooks->stop writes the
// checkpoint and its outputs. A failed simulation writes the checkpoint of its last good state; a
// finished run removes a stale one. With config.write_outputs false nothing is written (no checkpoint
// either: the caller keeps the returned state).
SimResult simulate(const CaseConfig& config, const MeshInputs& inputs, NodeSet& nodes,
                   const SimState* resume = nullptr, const SimulateHooks* hooks = nullptr, RunPhases* run = nullptr);

// Stage 7: triangulates `nodes`, checks the mesh when config.check (SimulationError listing the
// problems if it fails), measures quality, prints the table, and writes DIR/quality.json, the mesh
// files of config.output.formats, mesh.nodes, mesh.png and mesh_<view>.png (png), mesh.svg (svg); with
// cleanup.enabled the cleaned mesh. Waits for every picture queued in `run` before it returns. With
// config.write_outputs false it stops after the cleanup: no table, no quality summary, no files.
// `triangulated` (optional): a mesh already made of these nodes (SimResult::final_mesh), used instead
// of triangulating them again when it is theirs (triangulates()).
Mesh mesh_and_measure(const CaseConfig& config, const MeshInputs& inputs, const NodeSet& nodes,
                      RunPhases* run = nullptr, const Mesh* triangulated = nullptr);

// All stages in order (or, with config.resume, from the checkpoint on); progress on stderr unless
// config.quiet. Returns the exit status: 0, or 130 when interrupted (app/pipeline/stop_report: the checkpoint
// of the current nodes once the simulation has run, nothing else, and a message on stderr with the
// commands that continue). With config.resume and simulation.iterations 0 the checkpoint's nodes are
// meshed as they are (the checkpoint is kept). Every phase is timed: a summary line on stderr, and the
// JSON in config.timings_file when set.
int run_mesh(const CaseConfig& config);

}  // namespace pdmesh
