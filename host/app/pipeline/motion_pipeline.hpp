// `pdmesh mesh` on a case with [motion] (docs/motion.md): a mesh that moves with the named curves.
// Step 0 is a normal cold run on the geometry at t = 0. Each later step k (t = k / steps) carries the
// previous step's nodes along with the curves' rigid motion (motion/carry.hpp, never inverting a
// triangle of the previous mesh), rebuilds the geometry and the spacing field on the moved curves,
// relaxes the carried nodes for motion.iterations iterations with population control, triangulates
// and cleans up. The nodes keep their persistent ids through all of it (NodeSet::id); new nodes get
// new ids. Outputs: DIR/step_NNNN/mesh.<format> with point data node_id, DIR/motion.pvd, DIR/motion.json.
// The steps are a MotionStepper's (motion_stepper.hpp), given the poses of the case's expressions.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/motion_stepper.hpp"
#include "io/pvd_writer.hpp"

namespace pdmesh {

// Runs every step; `each` (when set) receives each step as it finishes (its record's wall_s and cpu_s
// include writing its outputs). With config.write_outputs the outputs above are written (each
// atomically; motion.json and motion.pvd rewritten after every step).
// Throws InputError (exit 2) before anything is written when [motion] names an unknown curve, when a
// motion expression is not finite at some step's t, or with [[boundary_layer]], a metric field or
// --resume, which the motion does not support.
void run_motion_steps(const CaseConfig& config, const std::function<void(const MotionStep&)>& each = {});

// The command: run_motion_steps with the progress lines, the interrupt guard and the output checks of
// run_mesh. Returns the exit status (0, or 130 when interrupted).
int run_motion(const CaseConfig& config);

// The files of a motion run in config.out_dir, step by step: DIR/step_NNNN/ (mesh.vtu, the other mesh
// formats of output.formats, mesh.png with png), and motion.pvd and motion.json rewritten with the
// steps so far, so that a stopped run lists its finished steps. The constructor creates DIR.
class MotionWriter {
 public:
  explicit MotionWriter(const CaseConfig& config);
  // Writes the step's files (the layer cells and core of `step.mixed` when it has cells, else
  // `step.mesh`); its record, with the time writing took added to wall_s and cpu_s, goes into motion.json.
  void write(const MotionStep& step, MotionStepRecord& record);
  const std::vector<MotionStepRecord>& records() const { return records_; }

 private:
  CaseConfig config_;
  std::vector<MotionStepRecord> records_;
  std::vector<PvdEntry> pvd_;
};

// DIR/motion.json's text for these records.
std::string motion_json(const std::vector<MotionStepRecord>& records);

}  // namespace pdmesh
