// `pdmesh mesh` on a case with [motion] (docs/motion.md): a mesh that moves with the named curves.
// Step 0 is a normal cold run on the geometry at t = 0. Each later step k (t = k / steps) carries the
// previous step's nodes along with the curves' rigid motion (motion/carry.hpp, never inverting a
// triangle of the previous mesh), rebuilds the geometry and the spacing field on the moved curves,
// relaxes the carried nodes for motion.iterations iterations with population control, triangulates
// and cleans up. The nodes keep their persistent ids through all of it (NodeSet::id); new nodes get
// new ids. Outputs: DIR/step_NNNN/mesh.<format> with point data node_id, DIR/motion.pvd, DIR/motion.json.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "io/mixed_mesh.hpp"
#include "mesh/mesh.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

// One step's record (a row of motion.json).
struct MotionStepRecord {
  int step = 0;
  double t = 0.0;
  double wall_s = 0.0;
  double cpu_s = 0.0;  // the process's CPU time over the step (all threads)
  int iterations = 0;
  std::size_t nodes = 0;
  double ids_kept = 1.0;  // share of the previous step's ids this step still has (1 at step 0)
  double min_angle = 0.0;
  std::size_t inverted = 0;  // triangles with orientation <= 0 (0 in a valid mesh)
  int carry_substeps = 0;    // sub-steps the carry needed (0 at step 0)
  double spacing_s = 0.0;    // of wall_s: reading the moved geometry and rebuilding the spacing field
  double simulation_s = 0.0;
  double cleanup_s = 0.0;
  // With [[boundary_layer]] (layer_motion.hpp): min_angle is the core's, nodes, ids_kept and inverted
  // count every node and cell; the layer cells and their measures (layers/layer_measures.hpp) over all
  // tables. layer_cells is 0 without layers.
  std::size_t layer_cells = 0;
  std::size_t layer_inverted = 0;
  double layer_max_angle = 0.0;
  double layer_first_height_within_2pct = 0.0;
  double layer_growth_max = 0.0;
  std::size_t steep_junctions = 0;  // layer tops given a pinned first-row node of the core
};

// One finished step for a caller that keeps the meshes (tests, the Python API): the cleaned mesh
// with point data node_id, its nodes (with ids, one per mesh point), and the record. With
// [[boundary_layer]] `mixed` holds the layer cells and core triangles, and `mesh` is it as triangles.
struct MotionStep {
  Mesh mesh;
  NodeSet nodes;
  MotionStepRecord record;
  MixedMesh mixed;
};

// Runs every step; `each` (when set) receives each step as it finishes. With config.write_outputs the
// outputs above are written (each atomically; motion.json and motion.pvd rewritten after every step).
// Throws InputError (exit 2) before anything is written when [motion] names an unknown curve, when a
// motion expression is not finite at some step's t, for a [[boundary_layer]] table whose walls move
// only in part, or with a metric field or --resume, which the motion does not support.
void run_motion_steps(const CaseConfig& config, const std::function<void(const MotionStep&)>& each = {});

// The command: run_motion_steps with the progress lines, the interrupt guard and the output checks of
// run_mesh. Returns the exit status (0, or 130 when interrupted).
int run_motion(const CaseConfig& config);

// DIR/motion.json's text for these records.
std::string motion_json(const std::vector<MotionStepRecord>& records);

}  // namespace pdmesh
