// The moving-geometry steps (motion_stepper.hpp; docs/motion.md).
#include "app/pipeline/motion_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/pipeline/layer_motion.hpp"
#include "app/pipeline/interrupt.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/pipeline_detail.hpp"
#include "cleanup/cleanup.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/predicates.hpp"
#include "core/worker_pool.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "motion/carry.hpp"
#include "nodes/node_domain.hpp"
#include "nodes/node_ids.hpp"

namespace pdmesh {

using mesh_detail::progress;

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

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The curves' indices by `curves.names`, or InputError naming `curves.key` and the unknown name.
std::vector<char> moving_curves(const MovingCurves& curves, const Geometry& geometry) {
  std::vector<char> moving(geometry.curves.size(), 0);
  std::vector<std::string> names;
  for (const Curve& c : geometry.curves) names.push_back(c.name);
  if (curves.names.empty())
    throw InputError(
        fmt::format("{}: no moving curve named (the geometry's curves: {})", curves.key, fmt::join(names, ", ")));
  for (const std::string& name : curves.names) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end())
      throw InputError(fmt::format("{}: unknown curve '{}' (the geometry's curves: {})", curves.key, quote_input(name),
                                   fmt::join(names, ", ")));
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

// A later step's cleanup works near the triangles below the target only: the topology pass on them,
// the smoothing sweeps on the vertices of the triangles below the target + kWarmSmoothMargin degrees.
// The carried and relaxed lattice is the previous step's cleaned one, with few triangles below the
// target. A cold mesh's limits (target + 15 and + 20 degrees) take in nearly every triangle of such a
// lattice: on the NACA 0012 pitching example the topology pass spent the whole trial budget and the
// sweeps went over the whole mesh at every step, for a mean aspect ratio 0.002 lower and the same
// smallest angle (docs/motion.md, "A step").
constexpr double kWarmSmoothMargin = 5.0;

CleanupOptions warm_cleanup_options(const CaseConfig& config) {
  CleanupOptions o = mesh_detail::cleanup_options(config);
  o.topology_below = o.min_angle;
  o.smooth_below = std::min(o.min_angle + kWarmSmoothMargin, 59.0);
  return o;
}

// The moved field's quadtree is held to twice the relative tolerance of step 0's
// (BackgroundOptions::tolerance): it approximates step 0's tree, itself within 1 %, and a 2 % error
// in q is far inside what a step's relaxation resolves; it builds in about two thirds of the time.
BackgroundOptions moved_background_options() {
  BackgroundOptions o;
  o.tolerance = 2.0 * o.tolerance;
  return o;
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

// The step's relaxation: step 0 as `pdmesh mesh` simulates; a later step on step 0's backend with the
// moved field's quadtree as the background.
void relax_step(const CaseConfig& sim_config, const MeshInputs& now, const SpacingStage& rest_spacing,
                BackgroundSpacing* moved_background, ChosenBackend& backend, SimulateHooks& hooks, NodeSet& nodes,
                MotionStepRecord& rec) {
  const auto sim_start = Clock::now();
  if (sim_config.simulation.iterations > 0 && rec.step == 0) {
    rec.iterations = simulate(sim_config, now, rest_spacing, nodes, nullptr, &hooks).state.iterations_done;
  } else if (sim_config.simulation.iterations > 0) {
    SimOptions options = simulation_options(sim_config, nodes.size());
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
    CleanupResult cleaned =
        clean_mesh(mesh, nodes, now.node_tree(), field,
                   rec.step == 0 ? mesh_detail::cleanup_options(config) : warm_cleanup_options(config));
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

}  // namespace

void refuse_unsupported_motion(const CaseConfig& config) {
  if (config.spacing.metric())
    throw InputError(fmt::format("{}: [motion] with a metric spacing field is not supported (docs/motion.md)",
                                 config.source.string()));
  if (config.resume)
    throw InputError(fmt::format("{}: --resume is not supported with [motion]", config.source.string()));
}

MotionStepper::MotionStepper(const CaseConfig& config, const MovingCurves& curves, const RigidPose& start)
    : config_(config), t0_(Clock::now()), c0_(std::clock()), start_pose_(start), pose_(start) {
  refuse_unsupported_motion(config);
  check_pose(start, "the start pose");
  config_.write_outputs = false;
  auto inputs = std::make_unique<MeshInputs>(config_);
  moving_ = moving_curves(curves, inputs->geometry);
  input_geometry_ = inputs->geometry;  // the curves at rest (each step's pose applied to them)
  step_config_ = config_;
  if (!start.identity()) {
    step_config_.geometry.given_curves = posed_curves(input_geometry_, moving_, start);
    inputs = std::make_unique<MeshInputs>(step_config_);
  }
  auto spacing = std::make_unique<SpacingStage>(step_config_, *inputs);
  if (!config_.boundary_layers.empty()) {
    // The steps mesh the core (the case on the layers' fronts, whose moving fronts are its moving
    // curves); the layers move rigidly with the body (layer_motion.hpp).
    layers_ = std::make_unique<LayerMotion>(step_config_, std::move(inputs), std::move(spacing), start);
    step_config_ = layers_->core_config();
    inputs = layers_->take_core_inputs();
    spacing = layers_->take_core_spacing();
    moving_ = layers_->core_moving();
    input_geometry_ = layers_->core_rest_geometry();
  }
  const double estimate = check_node_limit(step_config_, *inputs, *spacing);
  rest_inputs_ = std::move(inputs);
  rest_spacing_ = std::move(spacing);
  now_ = rest_inputs_.get();
  start_workers();
  const auto note = [this](const std::string& line) { progress(config_, "{}", line); };
  backend_ = choose_backend_for(config_.simulation.device, config_.simulation.precision, estimate, note);
}

MotionStepper::~MotionStepper() = default;

void MotionStepper::check_pose(const RigidPose& pose, const std::string& what) const {
  if (!std::isfinite(pose.angle) || !std::isfinite(pose.pivot.x) || !std::isfinite(pose.pivot.y) ||
      !std::isfinite(pose.shift.x) || !std::isfinite(pose.shift.y))
    throw InputError(fmt::format("{}: the pose is not finite: rotate {} deg about ({}, {}), translate ({}, {})", what,
                                 pose.angle * 180.0 / M_PI, pose.pivot.x, pose.pivot.y, pose.shift.x, pose.shift.y));
  if (pose.pivot.x != start_pose_.pivot.x || pose.pivot.y != start_pose_.pivot.y)
    throw InputError(
        fmt::format("{}: the pivot ({}, {}) is not the start pose's ({}, {}): every pose turns about one "
                    "pivot",
                    what, pose.pivot.x, pose.pivot.y, start_pose_.pivot.x, start_pose_.pivot.y));
}

void MotionStepper::check_usable(const char* what) const {
  if (failed_) throw SimulationError(fmt::format("{}: an earlier motion step failed part way; start a new run", what));
}

const MotionStep& MotionStepper::start(double t) {
  if (started_) throw std::logic_error("MotionStepper::start called twice");
  check_usable("motion step 0");
  failed_ = true;  // until the step is complete
  MotionStepRecord rec;
  rec.step = 0;
  rec.t = t;
  rec.spacing_s = since(t0_);
  InitialDistribution initial = make_initial(step_config_, *rest_inputs_, *rest_spacing_);
  NodeSet nodes = std::move(initial.nodes);
  SimulateHooks hooks;
  hooks.backend = [this](const std::function<void(const std::string&)>&) -> ChosenBackend& { return backend_; };
  relax_step(step_config_, *now_, *rest_spacing_, nullptr, backend_, hooks, nodes, rec);
  finish(std::move(nodes), rest_spacing_->field(), t0_, c0_, rec);
  started_ = true;
  return current();
}

const MotionStep& MotionStepper::step(const RigidPose& pose, double t) {
  if (!started_) throw std::logic_error("MotionStepper::step called before start");
  const std::string what = fmt::format("motion step {} (t = {})", current_.record.step + 1, t);
  check_usable(what.c_str());
  check_pose(pose, what);
  const auto step_start = Clock::now();
  const std::clock_t c0 = std::clock();
  MotionStepRecord rec;
  rec.step = current_.record.step + 1;
  rec.t = t;
  NodeSet placed;  // with layers: the previous nodes, the last steep junctions' pins released
  if (layers_) {
    failed_ = true;  // the layers are placed at `pose` from here on
    placed = current_.nodes;
    layers_->place(rec.step, t, pose, placed);
  }
  const NodeSet& previous = layers_ ? placed : current_.nodes;
  // Carry the previous nodes with the motion from the previous pose to this one.
  CarryRequest carry;
  carry.nodes = &previous;
  carry.triangles = &current_.mesh.triangles;
  carry.tree = &now_->node_tree();
  carry.moving = moving_;
  carry.radius = blend_radius(config_, now_->node_tree(), moving_);
  carry.from = pose_;
  carry.to = pose;
  const CarryResult carried = carry_nodes(carry);
  rec.carry_substeps = carried.substeps;
  // The moved geometry (read before anything changes: a pose whose curves cross is refused with the
  // stepper as it was), and step 0's spacing field moved with the body.
  const auto spacing_start = Clock::now();
  CaseConfig step_config = step_config_;
  step_config.geometry.given_curves = posed_curves(input_geometry_, moving_, pose);
  auto inputs = std::make_unique<MeshInputs>(step_config);
  failed_ = true;  // until the step is complete
  step_config_ = std::move(step_config);
  moved_background_.reset();
  moved_.reset();
  moved_inputs_ = std::move(inputs);
  now_ = moved_inputs_.get();
  const auto [centre, inner] = body_circle(rest_inputs_->geometry, moving_);
  moved_ = std::make_unique<MovedSpacing>(rest_spacing_->background(), start_pose_, pose, centre, inner, carry.radius);
  moved_background_ = std::make_unique<BackgroundSpacing>(*moved_, now_->node_tree(), moved_background_options());
  rec.spacing_s = since(spacing_start);
  NodeSet nodes = previous;
  nodes.x = carried.x;
  settle_on_moved_curves(nodes, moving_nodes(nodes, moving_), now_->node_tree(), moving_);
  moved_background_->at_many(nodes.x, nodes.q);
  pose_ = pose;
  // Relax, triangulate, clean up.
  SimulateHooks hooks;
  relax_step(warm_config(step_config_), *now_, *rest_spacing_, moved_background_.get(), backend_, hooks, nodes, rec);
  finish(std::move(nodes), *moved_background_, step_start, c0, rec);
  return current();
}

void MotionStepper::finish(NodeSet nodes, const SpacingField& field, Clock::time_point step_start, std::clock_t c0,
                           MotionStepRecord& rec) {
  const auto remesh = [&](NodeSet& n) {
    const double spent = rec.cleanup_s;
    Mesh m = mesh_step(config_, *now_, field, n, rec);
    rec.cleanup_s += spent;
    return m;
  };
  Mesh mesh = layers_ ? layers_->mesh_core(nodes, config_.cleanup.enabled, remesh) : remesh(nodes);
  number_new_nodes(nodes, next_id_);
  field.at_many(mesh.points, mesh.spacing);
  // The mesh's q as asked, as SpacingStage::asked() gives it (the nodes relax at relax_scale x it).
  for (double& v : mesh.spacing) v *= 1.0 / rest_spacing_->relax_scale();
  PointValues ids{"node_id", 1, {}, true};
  ids.values.assign(nodes.id.begin(), nodes.id.end());
  mesh.point_data.push_back(std::move(ids));
  measure_step(mesh, nodes, current_.nodes, rec);
  check_step(config_, *now_, mesh, nodes, rec);
  if (layers_) joined_ = layers_->join(*now_, mesh, nodes, rec, next_id_);
  rec.wall_s = since(step_start);
  rec.cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  current_ = MotionStep{std::move(mesh), std::move(nodes), rec, {}};
  joined_.record = rec;
  failed_ = false;
}

}  // namespace pdmesh
