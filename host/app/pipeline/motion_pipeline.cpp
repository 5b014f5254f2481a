// The moving-geometry run (motion_pipeline.hpp; docs/motion.md).
#include "app/pipeline/motion_pipeline.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <optional>
#include <fmt/format.h>

#include "app/pipeline/exit_codes.hpp"
#include "app/pipeline/interrupt.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/output_guard.hpp"
#include "app/pipeline/periodic_pipeline.hpp"
#include "app/pipeline/pipeline_detail.hpp"
#include "core/atomic_file.hpp"
#include "core/g17.hpp"
#include "core/interrupt.hpp"
#include "core/progress_notes.hpp"
#include "app/pipeline/layer_motion.hpp"
#include "io/mesh_formats.hpp"
#include "io/pvd_writer.hpp"
#include "motion/rigid_motion.hpp"
#include "render/mesh_picture.hpp"

namespace pdmesh {

namespace fs = std::filesystem;
using mesh_detail::progress;

namespace {

using Clock = std::chrono::steady_clock;

std::string step_name(int k) { return fmt::format("step_{:04d}", k); }

}  // namespace

namespace {

// With [[boundary_layer]], the layer cells' keys of a motion.json row; nothing without layers.
std::string layer_json(const MotionStepRecord& r) {
  if (r.layer_cells == 0) return {};
  std::string out = fmt::format(", \"layer_cells\": {}, \"layer_inverted\": {}, \"layer_max_angle\": ", r.layer_cells,
                                r.layer_inverted);
  append_g17(out, r.layer_max_angle);
  out += ", \"layer_first_height_within_2pct\": ";
  append_g17(out, r.layer_first_height_within_2pct);
  out += ", \"layer_growth_max\": ";
  append_g17(out, r.layer_growth_max);
  out += fmt::format(", \"steep_junctions\": {}", r.steep_junctions);
  return out;
}

}  // namespace

std::string motion_json(const std::vector<MotionStepRecord>& records) {
  std::string out = "[\n";
  for (std::size_t k = 0; k < records.size(); ++k) {
    const MotionStepRecord& r = records[k];
    const auto num = [](double v) {
      std::string s;
      append_g17(s, std::isfinite(v) ? v : 0.0);
      return s;
    };
    out += fmt::format(
        "  {{\"step\": {}, \"t\": {}, \"wall_s\": {}, \"cpu_s\": {}, \"iterations\": {}, \"nodes\": {}, \"ids_kept\": "
        "{}, "
        "\"min_angle\": {}, \"inverted\": {}, \"carry_substeps\": {}, \"spacing_s\": {}, \"simulation_s\": {}, "
        "\"cleanup_s\": {}{}}}{}\n",
        r.step, num(r.t), num(r.wall_s), num(r.cpu_s), r.iterations, r.nodes, num(r.ids_kept), num(r.min_angle),
        r.inverted, r.carry_substeps, num(r.spacing_s), num(r.simulation_s), num(r.cleanup_s), layer_json(r),
        k + 1 < records.size() ? "," : "");
  }
  out += "]\n";
  return out;
}

namespace {

// DIR/step_NNNN/: mesh.vtu, the other mesh formats asked for, and mesh.png.
void write_step_files(const CaseConfig& config, const MotionStepRecord& rec, const Mesh& mesh) {
  const fs::path dir = config.out_dir / step_name(rec.step);
  fs::create_directories(dir);
  std::vector<std::string> formats{"vtu"};
  for (const std::string& f : config.output.formats)
    if (is_mesh_format(f) && f != "vtu") formats.push_back(f);
  MeshWriteOptions write_options;
  write_options.walls = wall_curves(config);
  write_mesh(mesh, dir, "mesh", formats, write_options);
  if (config.output.wants("png")) {
    MeshPictureOptions picture;
    picture.title =
        fmt::format("{} - step {} t = {:.4g} ({} triangles)", config.name, rec.step, rec.t, mesh.triangles.size());
    if (!config.output.views.empty()) picture.window = config.output.views.front().window;
    write_mesh_picture(dir / "mesh.png", mesh, picture);
  }
}

// The step's line on the progress sink.
void report_step(const CaseConfig& config, const MotionStepRecord& rec) {
  progress(config,
           "motion: step {}/{} t = {:.4g}: {} nodes, {:.1f} % of the ids kept, min angle {:.2f} deg, {} inverted, "
           "{} iterations, carry in {} sub-step(s); {:.3f} s (spacing {:.3f}, simulation {:.3f}, mesh and cleanup "
           "{:.3f})",
           rec.step, config.motion.steps, rec.t, rec.nodes, 100.0 * rec.ids_kept, rec.min_angle, rec.inverted,
           rec.iterations, rec.carry_substeps, rec.wall_s, rec.spacing_s, rec.simulation_s, rec.cleanup_s);
}

}  // namespace

MotionWriter::MotionWriter(const CaseConfig& config) : config_(config) { prepare_output_directory(config_); }

void MotionWriter::write(const MotionStep& step, MotionStepRecord& record) {
  const auto write_start = Clock::now();
  const std::clock_t c0 = std::clock();
  if (step.mixed.cells.empty())
    write_step_files(config_, record, step.mesh);
  else
    LayerMotion::write_step_files(config_, config_.out_dir / step_name(record.step), step.mixed, step.mesh, record);
  record.wall_s += std::chrono::duration<double>(Clock::now() - write_start).count();
  record.cpu_s += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  records_.push_back(record);
  pvd_.push_back({record.t, step_name(record.step) + "/mesh.vtu"});
  write_pvd(config_.out_dir / "motion.pvd", pvd_);
  write_file_atomically(config_.out_dir / "motion.json", motion_json(records_));
}

void run_motion_steps(const CaseConfig& config, const std::function<void(const MotionStep&)>& each) {
  const CaseConfig::Motion& m = config.motion;
  refuse_unsupported_motion(config);
  CaseConfig base = config;
  base.write_outputs = false;
  // Every pose before anything runs: an expression that is not finite at some step is bad input.
  const MotionPath path(m.rotate, m.pivot, m.translate);
  std::vector<RigidPose> poses;
  for (std::int64_t k = 0; k <= m.steps; ++k)
    poses.push_back(path.at(static_cast<double>(k) / static_cast<double>(m.steps)));

  MotionStepper stepper(base, {m.curves, config.source.string() + ": motion.curves"}, poses[0]);
  std::optional<MotionWriter> writer;
  if (config.write_outputs) writer.emplace(config);
  for (int k = 0; k <= static_cast<int>(m.steps); ++k) {
    const double t = static_cast<double>(k) / static_cast<double>(m.steps);
    const MotionStep& step = k == 0 ? stepper.start(t) : stepper.step(poses[static_cast<std::size_t>(k)], t);
    MotionStepRecord rec = step.record;
    if (writer) writer->write(step, rec);
    report_step(config, rec);
    if (each) each(MotionStep{step.mesh, step.nodes, rec, step.mixed});
    check_interrupt();
  }
}

int run_motion(const CaseConfig& config) {
  struct Notes {
    explicit Notes(bool quiet) {
      if (!quiet) set_progress_sink([](const std::string& line) { fmt::print(stderr, "{}\n", line); });
    }
    ~Notes() { set_progress_sink({}); }
  } notes(config.quiet);
  InterruptGuard interrupt;
  check_periodic_case(config);
  check_outputs(config);
  try {
    run_motion_steps(config);
  } catch (const Interrupted&) {
    fmt::print(stderr, "pdmesh: stopped; the steps written so far are listed in {}\n",
               (config.out_dir / "motion.json").string());
    return kExitInterrupted;
  }
  return kExitOk;
}

}  // namespace pdmesh
