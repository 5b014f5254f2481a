// Boundary layers in a [motion] run (docs/motion.md, "Boundary layers"): the layers are built once, at
// step 0, on the case's geometry and field as `pdmesh mesh` builds them; the steps then mesh the core
// (the case on the layers' fronts). At each later step the layer cells of the moving curves move
// rigidly with the body (the same nodes, cells and ids: stretched, not regrown; the others stay),
// their fronts are the core's moving curves, and the core is carried, relaxed and cleaned as any
// motion step's; then the layer cells and the core's triangles are joined as in the layer pipeline.
// MotionStepper (motion_stepper.hpp) runs the steps; this class is its hook for the layers.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/layer_pipeline.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/motion_stepper.hpp"
#include "io/mixed_mesh.hpp"
#include "mesh/mesh.hpp"
#include "motion/rigid_motion.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

class LayerMotion {
 public:
  // Builds the layers of config's [[boundary_layer]] tables on `inputs` and `spacing` (the case's at
  // step 0's pose `pose0`; kept: the core's field refers to them) and the core's inputs and spacing on
  // their fronts; the curves of motion.curves move. InputError (before anything is written) for what
  // build_layers refuses, and for a table whose wall curves move only in part.
  LayerMotion(const CaseConfig& config, std::unique_ptr<MeshInputs> inputs, std::unique_ptr<SpacingStage> spacing,
              const RigidPose& pose0);

  // What the step loop meshes from here on: the core's case, its inputs and spacing at step 0 (handed
  // over once), per curve of the core's geometry whether it moves (the fronts of the moving walls,
  // and moving curves without layers), and the core's curves with the moving ones at rest (pose0
  // undone: a step's pose applied to them gives its fronts exactly where the layer nodes are).
  const CaseConfig& core_config() const { return layered_->core; }
  std::unique_ptr<MeshInputs> take_core_inputs() { return std::move(core_inputs_); }
  std::unique_ptr<SpacingStage> take_core_spacing() { return std::move(core_spacing_); }
  const std::vector<char>& core_moving() const { return core_moving_; }
  const Geometry& core_rest_geometry() const { return core_rest_; }

  // Before a later step's carry: the layers of the moving walls placed at `pose` (from their rest
  // places, so no error accumulates), and SimulationError naming the step and both curves when a
  // moved front would cross, or enclose, a core curve that does not move. The previous step's pinned
  // first-row nodes (place_first_row) become interior nodes again, to be carried and relaxed.
  void place(int step, double t, const RigidPose& pose, NodeSet& previous);

  // The relaxed core nodes meshed: without the nodes the simulation snapped onto a front (their ids
  // go), then, with the cleanup on, meshed again with a pinned first-row node at each steep junction
  // (layer_pipeline.hpp). `remesh` triangulates and cleans up, replacing the nodes by the cleaned ones.
  // The number of steep junctions found is the join's rec.steep_junctions.
  Mesh mesh_core(NodeSet& nodes, bool cleanup, const std::function<Mesh(NodeSet&)>& remesh);

  // The step's layer cells and core triangles as one mesh, point data node_id (the core nodes' ids,
  // then the layer nodes', numbered from `next_id` at step 0 and kept after). In `rec`: nodes and
  // ids_kept over all the mesh's nodes, inverted over its cells, the layers' measures; min_angle
  // stays the core's.
  MotionStep join(const MeshInputs& core_now, const Mesh& core_mesh, const NodeSet& core_nodes, MotionStepRecord& rec,
                  std::int64_t& next_id);

  // DIR/mesh.vtu (with node_id) and the mixed-cell formats of output.formats (msh, su2), and mesh.png
  // (the first of output.views as its window) when the case asks for png.
  // `mixed` is the step's joined mesh, `mesh` it as triangles (for the picture).
  static void write_step_files(const CaseConfig& config, const std::filesystem::path& dir, const MixedMesh& mixed,
                               const Mesh& mesh, const MotionStepRecord& rec);

 private:
  std::unique_ptr<MeshInputs> inputs_;  // the case's, at step 0
  std::unique_ptr<SpacingStage> spacing_;
  std::unique_ptr<LayeredCase> layered_;  // its sections' nodes at the current step's places
  std::unique_ptr<MeshInputs> core_inputs_;
  std::unique_ptr<SpacingStage> core_spacing_;
  std::vector<char> core_moving_;
  Geometry core_rest_;
  std::vector<std::uint8_t> section_moves_;    // per section
  std::vector<std::vector<Vec2>> rest_nodes_;  // per section: its nodes with pose0 undone
  std::vector<std::int64_t> layer_ids_;        // the ids of the nodes the join appends, in its order
  std::vector<std::int64_t> previous_ids_;     // the previous step's, for ids_kept
  std::vector<Vec2> embedded_;                 // the core's embedded points (Fixed, not pins)
  std::size_t steep_ = 0;                      // steep junctions of the last mesh_core
};

}  // namespace pdmesh
