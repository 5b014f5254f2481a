// pdmesh._core.MotionStepper: a moving-geometry run whose poses the caller gives one step at a time
// (app/pipeline/motion_stepper.hpp, the same steps as `pdmesh mesh` with [motion]); pdmesh.MovingMesher
// wraps it (docs/motion.md, "Stepping from Python"). The GIL is released while a step runs.
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "app/pipeline/motion_pipeline.hpp"
#include "app/pipeline/motion_stepper.hpp"
#include "bindings.hpp"
#include "core/errors.hpp"

namespace pdmesh::py {

namespace {

using Pair = std::array<double, 2>;

class Stepper {
 public:
  // warm_iterations < 0 and a NaN blend keep the case's motion.iterations and motion.blend.
  Stepper(const CaseConfig& config, const std::vector<std::string>& curves, Pair pivot, double rotate, Pair translate,
          std::int64_t warm_iterations, double blend, const std::string& out_dir) {
    CaseConfig c = config;
    c.quiet = true;  // the Python layer reports progress itself
    c.write_outputs = false;
    if (warm_iterations >= 0) {
      if (warm_iterations > 100000)
        throw InputError(fmt::format("warm_iterations must be in [0, 100000], got {}", warm_iterations));
      c.motion.iterations = warm_iterations;
    }
    if (!std::isnan(blend)) {
      if (!(blend > 0.0 && blend <= 1000.0))
        throw InputError(fmt::format("blend must be > 0 and at most 1000 (body sizes), got {}", blend));
      c.motion.blend = blend;
    }
    pivot_ = {pivot[0], pivot[1]};
    name_ = c.name;
    const RigidPose start = pose(rotate, translate);
    nb::gil_scoped_release release;
    stepper_ = std::make_unique<MotionStepper>(c, MovingCurves{curves, "moving"}, start);
    if (!out_dir.empty()) {
      CaseConfig w = c;
      w.out_dir = out_dir;
      w.write_outputs = true;
      writer_.emplace(w);
    }
    finished(stepper_->start(0.0));
  }

  // One step to the pose (absolute, degrees counter-clockwise about the pivot, then the translation).
  void step(double rotate, Pair translate, double t) {
    if (busy_) throw std::runtime_error("this MovingMesher is already stepping (in another thread)");
    busy_ = true;
    struct Done {
      bool& b;
      ~Done() { b = false; }
    } done{busy_};
    const RigidPose p = pose(rotate, translate);
    nb::gil_scoped_release release;
    finished(stepper_->step(p, t));
  }

  MeshHandle mesh() const { return mesh_; }
  const MotionStepRecord& record() const { return record_; }
  // A numpy copy: the stepper's ids change with the next step.
  nb::ndarray<nb::numpy, std::int64_t> ids() const {
    auto* v = new std::vector<std::int64_t>(stepper_->current().nodes.id);
    nb::capsule owner(v, [](void* p) noexcept { delete static_cast<std::vector<std::int64_t>*>(p); });
    return nb::ndarray<nb::numpy, std::int64_t>(v->data(), {v->size()}, owner);
  }
  std::string backend() const { return stepper_->backend(); }
  double rotate() const { return stepper_->pose().angle * 180.0 / M_PI; }
  Pair translate() const { return {stepper_->pose().shift.x, stepper_->pose().shift.y}; }

 private:
  RigidPose pose(double rotate, Pair translate) const {
    return pose_in_degrees(rotate, pivot_, {translate[0], translate[1]});
  }

  // The step's mesh handed to Python (a copy: the stepper keeps its own for the next carry), and its
  // files with out_dir.
  void finished(const MotionStep& s) {
    record_ = s.record;
    if (writer_) writer_->write(s, record_);
    mesh_.mesh = std::make_shared<const Mesh>(s.mesh);
    mesh_.name = name_;
  }

  std::unique_ptr<MotionStepper> stepper_;
  std::optional<MotionWriter> writer_;
  Vec2 pivot_;
  MeshHandle mesh_;
  MotionStepRecord record_;
  std::string name_;
  bool busy_ = false;
};

}  // namespace

nb::dict motion_record_dict(const MotionStepRecord& r) {
  nb::dict d;
  d["step"] = r.step;
  d["t"] = r.t;
  d["wall_s"] = r.wall_s;
  d["cpu_s"] = r.cpu_s;
  d["iterations"] = r.iterations;
  d["nodes"] = r.nodes;
  d["ids_kept"] = r.ids_kept;
  d["min_angle"] = r.min_angle;
  d["inverted"] = r.inverted;
  d["carry_substeps"] = r.carry_substeps;
  d["spacing_s"] = r.spacing_s;
  d["simulation_s"] = r.simulation_s;
  d["cleanup_s"] = r.cleanup_s;
  if (r.layer_cells > 0) {  // with [[boundary_layer]]: motion.json's layer keys
    d["layer_cells"] = r.layer_cells;
    d["layer_inverted"] = r.layer_inverted;
    d["layer_max_angle"] = r.layer_max_angle;
    d["layer_first_height_within_2pct"] = r.layer_first_height_within_2pct;
    d["layer_growth_max"] = r.layer_growth_max;
    d["steep_junctions"] = r.steep_junctions;
  }
  return d;
}

void bind_stepper(nb::module_& m) {
  nb::class_<Stepper>(m, "MotionStepper", "A moving-geometry run stepped pose by pose (use pdmesh.MovingMesher).")
      .def(nb::init<const CaseConfig&, const std::vector<std::string>&, Pair, double, Pair, std::int64_t, double,
                    const std::string&>(),
           nb::arg("config"), nb::arg("curves"), nb::arg("pivot"), nb::arg("rotate"), nb::arg("translate"),
           nb::arg("warm_iterations"), nb::arg("blend"), nb::arg("out_dir"),
           "Reads the case, places the moving curves at the start pose and runs step 0 (cold).")
      .def("step", &Stepper::step, nb::arg("rotate"), nb::arg("translate"), nb::arg("t"),
           "One warm step with the moving curves at this pose (degrees, translation).")
      .def_prop_ro("mesh", &Stepper::mesh, "The last step's mesh (point data node_id).")
      .def_prop_ro("record", [](const Stepper& s) { return motion_record_dict(s.record()); })
      .def_prop_ro("node_id", &Stepper::ids, nb::rv_policy::automatic,
                   "The last step's persistent node ids, one per point of its mesh (a copy).")
      .def_prop_ro("backend", &Stepper::backend)
      .def_prop_ro("rotate", &Stepper::rotate)
      .def_prop_ro("translate", &Stepper::translate);
}

}  // namespace pdmesh::py
