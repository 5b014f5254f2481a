// One moving-geometry run driven pose by pose (docs/motion.md, "A step"): the step loop of
// `pdmesh mesh` with [motion] (motion_pipeline.cpp), which hands it the poses of the case's
// expressions, and of Python's pdmesh.MovingMesher, whose caller decides each pose (a solver's loop).
// Step 0 is a normal cold run on the curves at the start pose; each later step carries the previous
// step's nodes along with the moving curves to the new pose, relaxes them warm, triangulates and cleans
// up, keeping the nodes' persistent ids (NodeSet::id).
#pragma once
#include <chrono>
#include <cstdint>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/backend_choice.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "io/mixed_mesh.hpp"
#include "mesh/mesh.hpp"
#include "motion/rigid_motion.hpp"
#include "nodes/node_set.hpp"
#include "spacing/background_field.hpp"

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

// One finished step: the cleaned mesh with point data node_id, its nodes (with ids), and the record.
struct MotionStep {
  Mesh mesh;
  NodeSet nodes;
  MotionStepRecord record;
  MixedMesh mixed;  // with [[boundary_layer]]: the layer cells and the core's triangles; `mesh` is it as triangles
};

// Which curves move, and how a message names where the names came from.
struct MovingCurves {
  std::vector<std::string> names;  // curve names of the geometry (geometry.curve_names or the files')
  std::string key;                 // e.g. "case.toml: motion.curves", or "moving" from Python
};

class LayerMotion;
class MovedSpacing;

// What a motion run cannot take (yet), refused before anything runs (InputError naming the case):
// [[boundary_layer]], a metric spacing field, --resume.
void refuse_unsupported_motion(const CaseConfig& config);

class MotionStepper {
 public:
  // Reads the geometry, places the moving curves at `start` and builds step 0's spacing field, checks
  // the node limit and chooses the backend; nothing is meshed yet. The case's motion.iterations and
  // motion.blend apply (their defaults without [motion]); its other [motion] keys are not read.
  // InputError: an unknown or no moving curve, a start pose that is not finite, a [[boundary_layer]]
  // table whose walls move only in part, a metric field or --resume; LimitError as `pdmesh mesh`.
  MotionStepper(const CaseConfig& config, const MovingCurves& curves, const RigidPose& start);
  ~MotionStepper();
  MotionStepper(const MotionStepper&) = delete;
  MotionStepper& operator=(const MotionStepper&) = delete;

  // Step 0 at time t: the initial distribution, the case's simulation, triangulation and cleanup.
  const MotionStep& start(double t);
  // The next step, at time t, with the moving curves at `pose` (absolute: from their place as read).
  // InputError when the pose is not finite or turns about another pivot than the start pose's, or when
  // the moved curves do not make a valid geometry (the stepper stays as it was, at the last step);
  // SimulationError when the carry would fold the mesh even in 256 sub-steps (likewise). A failure
  // after that (the relaxation's) leaves the stepper unusable: later calls throw SimulationError.
  // start() twice, or step() before start(), is a logic_error.
  const MotionStep& step(const RigidPose& pose, double t);

  bool started() const { return started_; }
  // The last step (empty before start()); with [[boundary_layer]] the layer cells and the core joined.
  const MotionStep& current() const { return layers_ ? joined_ : current_; }
  const RigidPose& pose() const { return pose_; }              // the moving curves' pose now
  const Geometry& geometry() const { return now_->geometry; }  // the geometry at the pose now
  // Where the simulation runs (Simulator::describe), once chosen.
  std::string backend() const { return backend_.simulator ? backend_.simulator->describe() : std::string(); }

 private:
  void check_pose(const RigidPose& pose, const std::string& what) const;
  void check_usable(const char* what) const;
  void finish(NodeSet nodes, const SpacingField& field, std::chrono::steady_clock::time_point step_start,
              std::clock_t c0, MotionStepRecord& rec);

  CaseConfig config_;  // the case, outputs off (the driver writes them)
  std::chrono::steady_clock::time_point t0_;
  std::clock_t c0_;
  std::vector<char> moving_;  // per curve: 1 if it moves
  Geometry input_geometry_;   // the curves as read, at rest
  RigidPose start_pose_, pose_;
  CaseConfig step_config_;                      // config_ with this step's curves (geometry.given_curves)
  std::unique_ptr<MeshInputs> rest_inputs_;     // step 0's geometry
  std::unique_ptr<SpacingStage> rest_spacing_;  // step 0's field: a later step's is it, moved
  std::unique_ptr<MeshInputs> moved_inputs_;    // a later step's geometry
  const MeshInputs* now_ = nullptr;             // this step's
  std::unique_ptr<MovedSpacing> moved_;
  std::unique_ptr<BackgroundSpacing> moved_background_;
  ChosenBackend backend_;  // step 0's choice, kept
  std::int64_t next_id_ = 0;
  bool started_ = false;
  bool failed_ = false;  // a step threw after it had begun to change the state
  MotionStep current_;   // the core's last step (the whole mesh without layers): the next step starts from it
  MotionStep joined_;    // with layers: current_ and the layer cells as one mesh
  std::unique_ptr<LayerMotion> layers_;
};

}  // namespace pdmesh
