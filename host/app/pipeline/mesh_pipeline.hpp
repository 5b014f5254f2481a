// `pdmesh mesh`: the pipeline for one validated case, in stages that each finish before the next
// begins, so that nothing is written until every input has been read and checked. The library that
// the command (run_mesh) and the Python binding (python/src/) both drive.
//
// The stages, in order; each takes the values of the ones before it and hands on its own:
//   1. read        MeshInputs (mesh_inputs.hpp)      the geometry, its trees, the base spacing field
//   2. spacing     SpacingStage, then check_node_limit  the final field and its quadtree; the limits
//   3. initial     InitialDistribution (make_initial)  the boundary nodes and the fill; then the output
//                  directory and the initial outputs
//   4. simulation  SimResult (simulate)              the particle dynamics, moving the initial nodes
//   5. mesh        Mesh (mesh_and_measure)           triangulation, check, cleanup, quality, mesh files
// The comments and the code name the stages by these names; the timed phases (run_phases.hpp) are
// finer ("fill", "final.nodes", "quality.json", ...).
#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <optional>

#include "app/config/case_file.hpp"
#include "app/pipeline/backend_choice.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/run_phases.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/mesh.hpp"
#include "sim/simulation.hpp"

namespace pdmesh {

// Stage initial, before its outputs: creates config.out_dir; InputError naming it when that fails.
void prepare_output_directory(const CaseConfig& config);

// DIR/spacing.png (and spacing_<view>.png per view): the final field's quadtree.
void write_spacing_picture(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing);

// The stages below time their phases in `run` and draw their pictures on its background thread;
// what a picture reads (the node sets passed in) must then stay unchanged until
// run->wait_pictures(). Without `run` the pictures are drawn before the stage returns.

// Stage initial, its outputs: DIR/initial.nodes, and as output.formats asks initial.png and
// initial_<view>.png per view (png), initial.svg (svg), each atomic.
void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs, const InitialDistribution& initial,
                           RunPhases* run = nullptr);
// The same, the pictures queued on `run` holding `initial` until they are drawn: the caller may let
// go of it at once, and the distribution (a node set as large as the run's) is freed when its last
// picture is done rather than at the end of the run.
void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs,
                           const std::shared_ptr<const InitialDistribution>& initial, RunPhases& run);

// The simulation settings of the case (iterations, stopping rule, time step, forces, population
// control); the backend, stop flag, background field and resume state are the caller's to add. `nodes`:
// the node count the automatic Verlet skin is chosen for (auto_verlet_skin; 0: a small run's).
SimOptions simulation_options(const CaseConfig& config, std::size_t nodes = 0);

// For callers that drive the stages themselves (the Python API, python/src/): a callback after every
// iteration, on top of the command's own, and the stop flag to poll instead of InterruptGuard::flag().
struct SimulateHooks {
  std::function<void(const HistoryRow&)> on_iteration;
  const std::atomic<bool>* stop = nullptr;
  // The backend, owned by the caller, who may keep it for later calls (a Mesher's steps) or set it up
  // beforehand (run_mesh does, on a thread, while the spacing field is built): called once when the
  // simulation begins, it passes its notes to `note`. Empty: simulate() calls choose_backend_for for
  // this call alone.
  std::function<ChosenBackend&(const std::function<void(const std::string&)>& note)> backend;
  // Non-null: receives the simulation's state as soon as it has ended normally (before its outputs
  // are written), so that a later stop request can checkpoint the finished nodes.
  std::optional<SimState>* finished = nullptr;
};

// Stage simulation: the particle dynamics simulation on the chosen backend, updating `nodes` in place,
// until it converges or for simulation.iterations (simulation.stop); writes DIR/history.csv, final.nodes,
// history.png, final.png and final_<view>.png (png), final.svg (svg).
// With `resume`, continues that state (nodes must be its node set). Stops early when core/interrupt's
// flag is set (a signal, or config.stop_after): then writes DIR/checkpoint.pdmesh and nothing else,
// and throws Interrupted naming the iteration and the file. A run stopped by hooks->stop writes the
// checkpoint and its outputs. A failed simulation writes the checkpoint of its last good state; a
// finished run removes a stale one. With config.write_outputs false nothing is written (no checkpoint
// either: the caller keeps the returned state).
SimResult simulate(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing, NodeSet& nodes,
                   const SimState* resume = nullptr, const SimulateHooks* hooks = nullptr, RunPhases* run = nullptr);

// Stage mesh: triangulates `nodes`, checks the mesh when config.check (SimulationError listing the
// problems if it fails), measures quality, prints the table, and writes DIR/quality.json, the mesh
// files of config.output.formats, mesh.nodes, mesh.png and mesh_<view>.png (png), mesh.svg (svg); with
// cleanup.enabled the cleaned mesh. Waits for every picture queued in `run` before it returns. With
// config.write_outputs false it stops after the cleanup: no table, no quality summary, no files.
// `triangulated` (optional): a mesh already made of these nodes (SimResult::final_mesh), used instead
// of triangulating them again when it is theirs (triangulates()).
Mesh mesh_and_measure(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
                      const NodeSet& nodes, RunPhases* run = nullptr, const Mesh* triangulated = nullptr);

// All stages in order (or, with config.resume, from the checkpoint on); progress on stderr unless
// config.quiet. Returns the exit status: 0, or 130 when interrupted (app/pipeline/stop_report: the checkpoint
// of the current nodes once the simulation has run, nothing else, and a message on stderr with the
// commands that continue). With config.resume and simulation.iterations 0 the checkpoint's nodes are
// meshed as they are (the checkpoint is kept). Every phase is timed: a summary line on stderr, and the
// JSON in config.timings_file when set.
int run_mesh(const CaseConfig& config);

}  // namespace pdmesh
