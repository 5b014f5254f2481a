// `pdmesh mesh`: the pipeline for one validated case, in stages that each finish before the next
// begins, so that nothing is written until every input has been read and checked.
#pragma once
#include <memory>

#include "app/case_file.hpp"
#include "app/run_phases.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/mesh.hpp"
#include "sim/simulation.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// Stage 1: the geometry, its tree and the spacing field; throws LimitError for coordinates too
// large to resolve at the segment lengths or the spacing (check_coordinate_resolution). Not
// movable: the tree and the boundary spacing field refer to the geometry.
struct MeshInputs {
  explicit MeshInputs(const CaseConfig& config);
  MeshInputs(const MeshInputs&) = delete;
  MeshInputs& operator=(const MeshInputs&) = delete;

  Geometry geometry;
  std::unique_ptr<GeometryTree> tree;
  std::unique_ptr<SpacingField> spacing;
  std::vector<std::string> curve_names() const;
};

// Stage 2: refuses, with LimitError naming the numbers, a case whose hexagonal-packing estimate
// (or requested total) exceeds config.max_nodes. Returns the estimate.
double check_node_limit(const CaseConfig& config, const MeshInputs& inputs);

// Stage 3: the initial distribution (boundary nodes and the tree fill).
InitialDistribution make_initial(const CaseConfig& config, const MeshInputs& inputs);

// Stage 4: creates config.out_dir; InputError naming it when that fails.
void prepare_output_directory(const CaseConfig& config);

// The stages below time their phases in `run` and draw their pictures on its background thread;
// what a picture reads (the node sets passed in) must then stay unchanged until
// run->wait_pictures(). Without `run` the pictures are drawn before the stage returns.

// Stage 5: DIR/initial.nodes, and as output.formats asks initial.png and initial_<view>.png per view
// (png), initial.svg (svg), each atomic.
void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs, const InitialDistribution& initial,
                           RunPhases* run = nullptr);

// The simulation settings of the case (iterations, stopping rule, time step, forces); the backend,
// stop flag and resume state are the caller's to add.
SimOptions simulation_options(const CaseConfig& config);

// Stage 6: the particle dynamics simulation on the chosen backend, updating `nodes` in place, until
// it converges or for simulation.iterations (simulation.stop); writes DIR/history.csv, final.nodes,
// history.png, final.png and final_<view>.png (png), final.svg (svg).
// With `resume`, continues that state (nodes must be its node set). Stops early when
// InterruptGuard::flag() is set (a signal, or config.stop_after); then, or when the simulation fails,
// writes DIR/checkpoint.pdmesh; a finished run removes a stale one.
SimResult simulate(const CaseConfig& config, const MeshInputs& inputs, NodeSet& nodes,
                   const SimState* resume = nullptr, RunPhases* run = nullptr);

// Stage 7: triangulates `nodes`, checks the mesh when config.check (SimulationError listing the
// problems if it fails), measures quality, prints the table, and writes DIR/quality.json, the mesh
// files of config.output.formats, mesh.png and mesh_<view>.png (png), mesh.svg (svg). Waits for
// every picture queued in `run` before it returns.
Mesh mesh_and_measure(const CaseConfig& config, const MeshInputs& inputs, const NodeSet& nodes,
                      RunPhases* run = nullptr);

// All stages in order (or, with config.resume, from the checkpoint on); progress on stderr unless
// config.quiet. Returns the exit status: 0, or 130 when interrupted (outputs of the state reached
// and a checkpoint written).
// Every phase is timed: a summary line on stderr, and the JSON in config.timings_file when set.
int run_mesh(const CaseConfig& config);

}  // namespace pdmesh
