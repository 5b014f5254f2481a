// The moving-geometry run (motion_pipeline.hpp; docs/motion.md).
#include "app/pipeline/motion_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/pipeline/backend_choice.hpp"
#include "app/pipeline/exit_codes.hpp"
#include "app/pipeline/interrupt.hpp"
#include "app/pipeline/layer_motion.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/output_guard.hpp"
#include "app/pipeline/pipeline_detail.hpp"
#include "cleanup/cleanup.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/g17.hpp"
#include "core/input_file.hpp"
#include "core/predicates.hpp"
#include "core/interrupt.hpp"
#include "core/progress_notes.hpp"
#include "core/worker_pool.hpp"
#include "io/mesh_formats.hpp"
#include "io/pvd_writer.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "motion/carry.hpp"
#include "motion/rigid_motion.hpp"
#include "nodes/node_domain.hpp"
#include "nodes/node_ids.hpp"
#include "render/mesh_picture.hpp"
#include "spacing/background_field.hpp"

namespace pdmesh {

namespace fs = std::filesystem;
using mesh_detail::progress;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The curves' indices by motion.curves, or InputError naming the case and the unknown name.
std::vector<char> moving_curves(const CaseConfig& config, const Geometry& geometry) {
  std::vector<char> moving(geometry.curves.size(), 0);
  std::vector<std::string> names;
  for (const Curve& c : geometry.curves) names.push_back(c.name);
  for (const std::string& name : config.motion.curves) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end())
      throw InputError(fmt::format("{}: motion.curves: unknown curve '{}' (the geometry's curves: {})",
                                   config.source.string(), quote_input(name), fmt::join(names, ", ")));
    moving[static_cast<std::size_t>(it - names.begin())] = 1;
  }
  return moving;
}

// The input curves with the moving ones placed by `pose` (the others as read).
std::vector<RawCurve> posed_curves(const Geometry& geometry, const std::vector<char>& moving, const RigidPose& pose) {
  std::vector<RawCurve> out;
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    RawCurve r;
    r.name = curve.name;
    r.file = curve.file;
    r.line = curve.line;
    r.fixed_points = curve.fixed_points;
    r.constraint = curve.constraint;
    r.points = curve.points;
    if (moving[c])
      for (Vec2& p : r.points) p = pose.apply(p);
    out.push_back(std::move(r));
  }
  return out;
}

// Where the carry's weight reaches 0: motion.blend body sizes (the diagonal of the moving curves'
// box), but no farther than 0.9 of the way to the nearest curve that does not move.
double blend_radius(const CaseConfig& config, const GeometryTree& tree, const std::vector<char>& moving) {
  const Geometry& g = tree.geometry();
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  std::vector<int> body;
  for (std::size_t c = 0; c < g.curves.size(); ++c) {
    if (!moving[c]) continue;
    body.push_back(static_cast<int>(c));
    for (const Vec2& p : g.curves[c].points)
      x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  double radius = config.motion.blend * std::hypot(x1 - x0, y1 - y0);
  for (std::size_t c = 0; c < g.curves.size(); ++c) {
    if (moving[c]) continue;
    const auto& pts = g.curves[c].points;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      for (const Vec2 p : {pts[k], k + 1 < pts.size() ? 0.5 * (pts[k] + pts[k + 1]) : pts[k]}) {
        for (const int b : body) radius = std::min(radius, 0.9 * tree.closest_on_curve(p, b).distance);
      }
    }
  }
  return radius;
}

// The spacing field of step 0 moved with the body: q(x) = q0(y), y = x + w(r) (P0(Pk^-1(x)) - x), with
// P0 and Pk the body's poses at step 0 and now, r the distance from the body's centre and w 1 within
// the body's circumscribed circle, falling smoothly to 0 at `outer` (the carry's radius). Near the
// body the field moves rigidly with it, beyond `outer` it stays. Its quadtree is built on the moved
// geometry (tags and refinement there) from lookups in step 0's quadtree: a fraction of a rebuild of
// the spacing pipeline (docs/motion.md, "The spacing field").
class MovedSpacing final : public SpacingField {
 public:
  MovedSpacing(const SpacingField& rest, const RigidPose& rest_pose, const RigidPose& pose, Vec2 centre, double inner,
               double outer)
      : rest_(rest),
        change_{pose, rest_pose},
        centre_(PoseChange{rest_pose, pose}(centre)),
        inner_(inner),
        outer_(std::max(outer, inner)) {}
  double at(Vec2 x) const override { return rest_.at(source(x)); }
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override {
    std::vector<Vec2> y(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) y[i] = source(p[i]);
    rest_.at_many(y, q);
  }

 private:
  Vec2 source(Vec2 x) const {
    const double r = std::sqrt(norm2(x - centre_));
    const double w = r <= inner_ ? 1.0 : carry_weight(r - inner_, outer_ - inner_);
    return w <= 0.0 ? x : x + w * (change_(x) - x);
  }
  const SpacingField& rest_;
  PoseChange change_;  // now -> step 0
  Vec2 centre_;        // the body's centre now
  double inner_, outer_;
};

// The centre and circumscribed radius of the moving curves' box.
std::pair<Vec2, double> body_circle(const Geometry& g, const std::vector<char>& moving) {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (std::size_t c = 0; c < g.curves.size(); ++c)
    if (moving[c])
      for (const Vec2& p : g.curves[c].points)
        x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  return {{0.5 * (x0 + x1), 0.5 * (y0 + y1)}, 0.5 * std::hypot(x1 - x0, y1 - y0)};
}

// The carried nodes of the moving curves placed exactly on the moved node geometry: Boundary nodes
// at the closest point of their curve, Fixed nodes at the nearest point of a moving curve.
void settle_on_moved_curves(NodeSet& nodes, const std::vector<char>& rigid, const GeometryTree& tree,
                            const std::vector<char>& moving) {
  const Geometry& g = tree.geometry();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (!rigid[i]) continue;
    if (nodes.kind[i] == NodeKind::Boundary) {
      nodes.x[i] = tree.closest_on_curve(nodes.x[i], nodes.curve[i]).point;
      continue;
    }
    double best = std::numeric_limits<double>::infinity();
    Vec2 at = nodes.x[i];
    for (std::size_t c = 0; c < g.curves.size(); ++c) {
      if (!moving[c]) continue;
      for (const Vec2& p : g.curves[c].points) {
        const double d = norm2(p - nodes.x[i]);
        if (d < best) best = d, at = p;
      }
    }
    nodes.x[i] = at;
  }
}

CleanupOptions cleanup_options(const CaseConfig& config) {
  CleanupOptions o;
  o.min_angle = config.cleanup.min_angle;
  o.iterations = static_cast<int>(config.cleanup.iterations);
  o.topology = config.cleanup.topology;
  o.split_boundary = config.cleanup.split_boundary;
  o.trials_per_triangle = config.cleanup.trials_per_triangle;
  o.min_trials = static_cast<double>(config.cleanup.min_trials);
  return o;
}

// The warm relaxation of a later step: motion.iterations iterations exactly, with two population
// events, a third and two thirds of the way. The carried nodes are the previous step's settled ones in
// a field moved with them, so the events find little to do, and each costs about as much as several
// iterations.
CaseConfig warm_config(const CaseConfig& base) {
  CaseConfig c = base;
  const auto n = static_cast<int>(base.motion.iterations);
  c.simulation.iterations = n;
  c.simulation.stop = StopRule::Iterations;
  c.population.start = std::max(1, n / 3);
  c.population.every = std::max(1, n / 3);
  c.population.stop = 0.75;
  c.quiet = true;
  return c;
}

// A later step's cleanup: the topology pass works only on the triangles below the target. The
// carried and relaxed lattice is the previous step's settled one, with few triangles below it; the
// pass over its 40-45 degree triangles that a cold mesh gets spent the whole trial budget at every
// step for no gain the motion's targets need (docs/motion.md, "A step").
CleanupOptions warm_cleanup_options(const CaseConfig& config) {
  CleanupOptions o = cleanup_options(config);
  o.topology_below = o.min_angle;
  return o;
}

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

// What a motion run cannot take (yet): refused before anything runs.
void refuse_unsupported(const CaseConfig& config) {
  if (config.spacing.metric())
    throw InputError(fmt::format("{}: [motion] with a metric spacing field is not supported (docs/motion.md)",
                                 config.source.string()));
  if (config.resume)
    throw InputError(fmt::format("{}: --resume is not supported with [motion]", config.source.string()));
}

// The step's figures from its mesh: node count, share of ids kept, smallest angle, inverted triangles.
void measure_step(const Mesh& mesh, const NodeSet& nodes, const NodeSet& previous, MotionStepRecord& rec) {
  rec.nodes = nodes.size();
  rec.ids_kept = rec.step == 0 || previous.size() == 0
                     ? 1.0
                     : static_cast<double>(ids_kept(previous.id, nodes.id)) / static_cast<double>(previous.size());
  double min_angle = 180.0;
  for (const TriangleQuality& q : triangle_qualities(mesh)) min_angle = std::min(min_angle, q.min_angle);
  rec.min_angle = mesh.triangles.empty() ? 0.0 : min_angle;
  rec.inverted = 0;
  for (const auto& t : mesh.triangles)
    rec.inverted += orient2d(mesh.points[static_cast<std::size_t>(t[0])], mesh.points[static_cast<std::size_t>(t[1])],
                             mesh.points[static_cast<std::size_t>(t[2])]) <= 0.0;
}

// DIR/step_NNNN/: mesh.vtu, the other mesh formats asked for, and mesh.png.
void write_step_files(const CaseConfig& config, const MotionStepRecord& rec, const Mesh& mesh) {
  const fs::path dir = config.out_dir / step_name(rec.step);
  fs::create_directories(dir);
  std::vector<std::string> formats{"vtu"};
  for (const std::string& f : config.output.formats)
    if (is_mesh_format(f) && f != "vtu") formats.push_back(f);
  write_mesh(mesh, dir, "mesh", formats);
  if (config.output.wants("png")) {
    MeshPictureOptions picture;
    picture.title =
        fmt::format("{} - step {} t = {:.4g} ({} triangles)", config.name, rec.step, rec.t, mesh.triangles.size());
    if (!config.output.views.empty()) picture.window = config.output.views.front().window;
    write_mesh_picture(dir / "mesh.png", mesh, picture);
  }
}

// The step's relaxation: step 0 as `pdmesh mesh` simulates; a later step on step 0's backend with the
// moved field's quadtree as the background.
void relax_step(const CaseConfig& sim_config, const MeshInputs& now, const SpacingStage& rest_spacing,
                BackgroundSpacing* moved_background, ChosenBackend& backend, SimulateHooks& hooks, NodeSet& nodes,
                MotionStepRecord& rec) {
  const auto sim_start = Clock::now();
  if (sim_config.simulation.iterations > 0 && rec.step == 0) {
    rec.iterations = simulate(sim_config, now, rest_spacing, nodes, nullptr, &hooks).state.iterations_done;
  } else if (sim_config.simulation.iterations > 0) {
    SimOptions options = simulation_options(sim_config);
    options.background = moved_background;
    options.stop = &InterruptGuard::flag();
    rec.iterations =
        backend.simulator->run(nodes, now.node_tree(), *moved_background, options, {}).state.iterations_done;
  }
  rec.simulation_s = since(sim_start);
}

// The relaxed nodes triangulated and cleaned up (step 0 with the case's cleanup, later steps with
// warm_cleanup_options); the nodes become the cleaned ones.
Mesh mesh_step(const CaseConfig& config, const MeshInputs& now, const SpacingField& field, NodeSet& nodes,
               MotionStepRecord& rec) {
  const auto cleanup_start = Clock::now();
  Mesh mesh = triangulate(nodes, now.curve_names());
  if (config.cleanup.enabled) {
    CleanupResult cleaned = clean_mesh(mesh, nodes, now.node_tree(), field,
                                       rec.step == 0 ? cleanup_options(config) : warm_cleanup_options(config));
    mesh = std::move(cleaned.mesh);
    nodes = std::move(cleaned.nodes);
  }
  rec.cleanup_s = since(cleanup_start);
  return mesh;
}

// With --check, the step's mesh through the invariant checker.
void check_step(const CaseConfig& config, const MeshInputs& now, const Mesh& mesh, const NodeSet& nodes,
                const MotionStepRecord& rec) {
  if (!config.check) return;
  const CheckReport report = check_mesh(mesh, node_domain_area(nodes, now.node_geometry()));
  if (!report.ok())
    throw SimulationError(fmt::format("motion step {} (t = {}): the mesh failed its invariant check:\n{}", rec.step,
                                      rec.t, report.summary()));
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

// motion.pvd and motion.json rewritten with the steps so far, so that a stopped run lists its steps.
void write_series(const CaseConfig& config, const std::vector<MotionStepRecord>& records, std::vector<PvdEntry>& pvd) {
  const MotionStepRecord& rec = records.back();
  pvd.push_back({rec.t, step_name(rec.step) + "/mesh.vtu"});
  write_pvd(config.out_dir / "motion.pvd", pvd);
  write_file_atomically(config.out_dir / "motion.json", motion_json(records));
}

// With [[boundary_layer]] the steps mesh the core, the case on the layers' fronts, whose moving fronts
// are its moving curves; the layers move rigidly with the body (layer_motion.hpp). The case's step-0
// config, inputs, spacing, moving curves and rest curves become the core's.
std::unique_ptr<LayerMotion> start_layers(CaseConfig& step_config, std::unique_ptr<MeshInputs>& inputs,
                                          std::unique_ptr<SpacingStage>& spacing, std::vector<char>& moving,
                                          Geometry& input_geometry, const RigidPose& pose0) {
  auto layers = std::make_unique<LayerMotion>(step_config, std::move(inputs), std::move(spacing), pose0);
  step_config = layers->core_config();
  inputs = layers->take_core_inputs();
  spacing = layers->take_core_spacing();
  moving = layers->core_moving();
  input_geometry = layers->core_rest_geometry();
  return layers;
}

}  // namespace

void run_motion_steps(const CaseConfig& config, const std::function<void(const MotionStep&)>& each) {
  const CaseConfig::Motion& m = config.motion;
  refuse_unsupported(config);
  CaseConfig base = config;
  base.write_outputs = false;
  // Every pose before anything runs: an expression that is not finite at some step is bad input.
  const MotionPath path(m.rotate, m.pivot, m.translate);
  std::vector<RigidPose> poses;
  for (std::int64_t k = 0; k <= m.steps; ++k)
    poses.push_back(path.at(static_cast<double>(k) / static_cast<double>(m.steps)));

  auto t0 = Clock::now();
  std::clock_t c0 = std::clock();
  auto inputs = std::make_unique<MeshInputs>(base);
  std::vector<char> moving = moving_curves(config, inputs->geometry);
  Geometry input_geometry = inputs->geometry;  // the curves at rest (t's pose applied to them)
  CaseConfig step_config = base;
  if (!poses[0].identity()) {
    step_config.geometry.given_curves = posed_curves(input_geometry, moving, poses[0]);
    inputs = std::make_unique<MeshInputs>(step_config);
  }
  auto spacing = std::make_unique<SpacingStage>(step_config, *inputs);
  const std::unique_ptr<LayerMotion> layers =
      config.boundary_layers.empty() ? nullptr
                                     : start_layers(step_config, inputs, spacing, moving, input_geometry, poses[0]);
  const double estimate = check_node_limit(step_config, *inputs, *spacing);
  // Step 0's inputs and field stay: the later steps' fields are it, moved (MovedSpacing).
  const std::unique_ptr<MeshInputs> rest_inputs = std::move(inputs);
  const std::unique_ptr<SpacingStage> rest_spacing = std::move(spacing);
  std::unique_ptr<MeshInputs> moved_inputs;   // a later step's geometry
  const MeshInputs* now = rest_inputs.get();  // this step's
  start_workers();
  if (config.write_outputs) prepare_output_directory(config);

  const auto note = [&config](const std::string& line) { progress(config, "{}", line); };
  ChosenBackend backend = choose_backend_for(config.simulation.device, config.simulation.precision, estimate, note);
  SimulateHooks hooks;
  hooks.backend = [&backend](const std::function<void(const std::string&)>&) -> ChosenBackend& { return backend; };

  std::vector<MotionStepRecord> records;
  std::vector<PvdEntry> pvd;
  std::int64_t next_id = 0;
  NodeSet previous;
  Mesh previous_mesh;
  std::unique_ptr<MovedSpacing> moved;
  std::unique_ptr<BackgroundSpacing> moved_background;
  for (int k = 0; k <= static_cast<int>(m.steps); ++k) {
    if (k > 0) c0 = std::clock();
    MotionStepRecord rec;
    rec.step = k;
    rec.t = static_cast<double>(k) / static_cast<double>(m.steps);
    NodeSet nodes;
    CaseConfig sim_config = step_config;
    if (k == 0) {
      rec.spacing_s = since(t0);
      InitialDistribution initial = make_initial(step_config, *rest_inputs, *rest_spacing);
      nodes = std::move(initial.nodes);
    } else {
      t0 = Clock::now();
      if (layers) layers->place(k, rec.t, poses[static_cast<std::size_t>(k)], previous);
      // Carry the previous nodes with the motion from the previous pose to this one.
      CarryRequest carry;
      carry.nodes = &previous;
      carry.triangles = &previous_mesh.triangles;
      carry.tree = &now->node_tree();
      carry.moving = moving;
      carry.radius = blend_radius(config, now->node_tree(), moving);
      carry.from = poses[static_cast<std::size_t>(k - 1)];
      carry.to = poses[static_cast<std::size_t>(k)];
      const CarryResult carried = carry_nodes(carry);
      rec.carry_substeps = carried.substeps;
      // The moved geometry, and step 0's spacing field moved with the body.
      const auto spacing_start = Clock::now();
      step_config.geometry.given_curves = posed_curves(input_geometry, moving, poses[static_cast<std::size_t>(k)]);
      moved_inputs = std::make_unique<MeshInputs>(step_config);
      now = moved_inputs.get();
      const auto [centre, inner] = body_circle(rest_inputs->geometry, moving);
      moved = std::make_unique<MovedSpacing>(rest_spacing->background(), poses[0], poses[static_cast<std::size_t>(k)],
                                             centre, inner, carry.radius);
      moved_background = std::make_unique<BackgroundSpacing>(*moved, now->node_tree());
      rec.spacing_s = since(spacing_start);
      nodes = previous;
      nodes.x = carried.x;
      settle_on_moved_curves(nodes, moving_nodes(nodes, moving), now->node_tree(), moving);
      moved_background->at_many(nodes.x, nodes.q);
      sim_config = warm_config(step_config);
    }
    // Relax, triangulate, clean up.
    relax_step(sim_config, *now, *rest_spacing, moved_background.get(), backend, hooks, nodes, rec);
    const SpacingField& field = k == 0 ? rest_spacing->field() : *moved_background;
    const auto remesh = [&](NodeSet& n) {
      const double spent = rec.cleanup_s;
      Mesh m = mesh_step(config, *now, field, n, rec);
      rec.cleanup_s += spent;
      return m;
    };
    Mesh mesh = layers ? layers->mesh_core(nodes, config.cleanup.enabled, remesh) : remesh(nodes);
    number_new_nodes(nodes, next_id);
    field.at_many(mesh.points, mesh.spacing);
    // The mesh's q as asked, as SpacingStage::asked() gives it (the nodes relax at relax_scale x it).
    for (double& v : mesh.spacing) v *= 1.0 / rest_spacing->relax_scale();
    PointValues ids{"node_id", 1, {}, true};
    ids.values.assign(nodes.id.begin(), nodes.id.end());
    mesh.point_data.push_back(std::move(ids));
    measure_step(mesh, nodes, previous, rec);
    check_step(config, *now, mesh, nodes, rec);
    std::optional<MotionStep> joined;  // with layers: the layer cells and the core as one mesh
    if (layers) joined = layers->join(*now, mesh, nodes, rec, next_id);
    if (config.write_outputs && joined) layers->write_step_files(config, config.out_dir / step_name(k), *joined);
    if (config.write_outputs && !joined) write_step_files(config, rec, mesh);
    rec.wall_s = since(t0);
    rec.cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    records.push_back(rec);
    if (config.write_outputs) write_series(config, records, pvd);
    report_step(config, rec);
    if (each && joined) joined->record = rec;
    if (each) each(joined ? *joined : MotionStep{mesh, nodes, rec, {}});
    check_interrupt();
    previous = std::move(nodes);
    previous_mesh = std::move(mesh);
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
