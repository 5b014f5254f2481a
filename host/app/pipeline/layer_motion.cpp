// Boundary layers that move with the body (layer_motion.hpp; docs/motion.md, "Boundary layers").
#include "app/pipeline/layer_motion.hpp"

#include <algorithm>
#include <limits>
#include <optional>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/pipeline/pipeline_detail.hpp"
#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "io/mesh_formats.hpp"
#include "layers/front_geometry.hpp"
#include "layers/layer_measures.hpp"
#include "nodes/node_ids.hpp"
#include "render/mesh_picture.hpp"

namespace pdmesh {

namespace fs = std::filesystem;
using mesh_detail::progress;

namespace {

bool named(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Whether segments ab and cd meet (crossing, touching, or overlapping on one line), exactly.
bool segments_meet(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double o1 = orient2d(a, b, c), o2 = orient2d(a, b, d), o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  if (o1 == 0.0 && o2 == 0.0) {  // on one line: do their extents overlap?
    return std::max(std::min(a.x, b.x), std::min(c.x, d.x)) <= std::min(std::max(a.x, b.x), std::max(c.x, d.x)) &&
           std::max(std::min(a.y, b.y), std::min(c.y, d.y)) <= std::min(std::max(a.y, b.y), std::max(c.y, d.y));
  }
  return ((o1 <= 0.0 && o2 >= 0.0) || (o1 >= 0.0 && o2 <= 0.0)) &&
         ((o3 <= 0.0 && o4 >= 0.0) || (o3 >= 0.0 && o4 <= 0.0));
}

// Whether p lies inside the closed polyline `loop` (even-odd rule).
bool inside_loop(Vec2 p, const std::vector<Vec2>& loop) {
  bool in = false;
  for (std::size_t k = 0; k + 1 < loop.size(); ++k) {
    const Vec2 a = loop[k], b = loop[k + 1];
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) in = !in;
  }
  return in;
}

Box box_of(const std::vector<Vec2>& pts) {
  Box b;
  for (const Vec2& p : pts) b.add(p);
  return b;
}

bool overlap(const Box& a, Vec2 p, Vec2 q) {
  return std::max(p.x, q.x) >= a.lo.x && std::min(p.x, q.x) <= a.hi.x && std::max(p.y, q.y) >= a.lo.y &&
         std::min(p.y, q.y) <= a.hi.y;
}

// The first point where the moving curve `m` meets the fixed curve `f`, or none.
std::optional<Vec2> first_meeting(const std::vector<Vec2>& m, const std::vector<Vec2>& f) {
  const Box mb = box_of(m);
  for (std::size_t j = 0; j + 1 < f.size(); ++j) {
    if (!overlap(mb, f[j], f[j + 1])) continue;
    for (std::size_t i = 0; i + 1 < m.size(); ++i)
      if (segments_meet(m[i], m[i + 1], f[j], f[j + 1])) return 0.5 * (m[i] + m[i + 1]);
  }
  return std::nullopt;
}

// Per layer node of `m`: 1 on a front (a node the core mesh shares).
std::vector<char> front_flags(const LayerMesh& m) {
  std::vector<char> on(m.nodes.size(), 0);
  for (std::size_t chain = 0; chain < m.fronts.size(); ++chain)
    for (const int n : core_front(m, chain).nodes) on[static_cast<std::size_t>(n)] = 1;
  return on;
}

}  // namespace

LayerMotion::LayerMotion(const CaseConfig& config, std::unique_ptr<MeshInputs> inputs,
                         std::unique_ptr<SpacingStage> spacing, const RigidPose& pose0)
    : inputs_(std::move(inputs)), spacing_(std::move(spacing)) {
  const std::vector<std::string>& motion_curves = config.motion.curves;
  layered_ = build_layers(config, *inputs_, *spacing_);
  // A table's layers move as one body or stay: its walls all move, or none does.
  std::vector<std::string> moving_fronts;
  for (std::size_t k = 0; k < layered_->sections.size(); ++k) {
    const LayerSection& s = layered_->sections[k];
    std::vector<std::string> moves, stays;
    for (const int w : s.walls) {
      const std::string& name = s.geometry->curves[static_cast<std::size_t>(w)].name;
      (named(motion_curves, name) ? moves : stays).push_back(name);
    }
    if (!moves.empty() && !stays.empty())
      throw InputError(fmt::format(
          "{}: [[boundary_layer]] table {}: its curves {} move ([motion] curves) and {} do not; the layers of one "
          "table move as one body: put the moving walls in a table of their own",
          config.source.string(), k + 1, fmt::join(moves, ", "), fmt::join(stays, ", ")));
    for (std::size_t c = 0; !moves.empty() && c < s.mesh.chain_closed.size(); ++c)
      if (s.mesh.chain_closed[c] == 0) {
        const LayerRay& first = s.mesh.rays[static_cast<std::size_t>(s.mesh.chain_ray_begin[c])];
        const LayerRay& last = s.mesh.rays[static_cast<std::size_t>(s.mesh.chain_ray_begin[c + 1] - 1)];
        const Vec2 a = s.mesh.nodes[static_cast<std::size_t>(first.wall_node)];
        const Vec2 b = s.mesh.nodes[static_cast<std::size_t>(last.wall_node)];
        throw InputError(fmt::format(
            "{}: [[boundary_layer]] table {}: the moving wall chain of curve \"{}\" is open (it ends at ({}, {}) "
            "and ({}, {})); a moving body's layers must go round it: add the curves that close its loop to the "
            "table and to [motion] curves",
            config.source.string(), k + 1, s.geometry->curves[static_cast<std::size_t>(first.curve)].name, a.x, a.y,
            b.x, b.y));
      }
    section_moves_.push_back(moves.empty() ? 0 : 1);
    rest_nodes_.push_back(s.mesh.nodes);
    if (moves.empty()) continue;
    for (Vec2& p : rest_nodes_.back()) p = pose0.apply_inverse(p);
    for (std::size_t c = 0; c + 1 < s.mesh.chain_ray_begin.size(); ++c) {
      const LayerRay& first = s.mesh.rays[static_cast<std::size_t>(s.mesh.chain_ray_begin[c])];
      moving_fronts.push_back(s.geometry->curves[static_cast<std::size_t>(first.curve)].name + "_front");
    }
  }
  core_inputs_ = layered_core_inputs(*layered_, *inputs_);
  core_inputs_->projection = inputs_->projection;
  core_spacing_ = std::make_unique<SpacingStage>(layered_->core, *core_inputs_);
  // The core's curves at rest: a step's pose applied to a moving front's points here gives exactly
  // the layer nodes that pose gives (the same arithmetic on the same numbers), which the join needs.
  core_rest_ = core_inputs_->geometry;
  for (const RawPoint& p : core_rest_.embedded_points) embedded_.push_back(p.p);
  for (Curve& c : core_rest_.curves) {
    const bool moves = named(motion_curves, c.name) || named(moving_fronts, c.name);
    core_moving_.push_back(moves ? 1 : 0);
    if (moves)
      for (Vec2& p : c.points) p = pose0.apply_inverse(p);
  }
}

void LayerMotion::place(int step, double t, const RigidPose& pose, NodeSet& previous) {
  for (std::size_t k = 0; k < layered_->sections.size(); ++k) {
    if (!section_moves_[k]) continue;
    std::vector<Vec2>& nodes = layered_->sections[k].mesh.nodes;
    for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i] = pose.apply(rest_nodes_[k][i]);
  }
  // The moved fronts (and other moving curves) against every curve that stays.
  const std::vector<Curve>& curves = core_rest_.curves;
  for (std::size_t m = 0; m < curves.size(); ++m) {
    if (!core_moving_[m]) continue;
    std::vector<Vec2> moved = curves[m].points;
    for (Vec2& p : moved) p = pose.apply(p);
    const bool closed = moved.size() > 2 && moved.front() == moved.back();
    for (std::size_t f = 0; f < curves.size(); ++f) {
      if (core_moving_[f]) continue;
      std::optional<Vec2> at = first_meeting(moved, curves[f].points);
      if (!at && closed && !curves[f].points.empty() && inside_loop(curves[f].points.front(), moved))
        at = curves[f].points.front();
      if (at)
        throw SimulationError(fmt::format(
            "motion step {} (t = {}): the curve '{}' (moving with the body) meets the curve '{}', which does not "
            "move, near ({:.6g}, {:.6g}); boundary layers move rigidly with the body and cannot pass a fixed curve "
            "(a smaller motion, or thinner layers)",
            step, t, curves[m].name, curves[f].name, at->x, at->y));
    }
  }
  // The previous step's pinned first-row nodes: Fixed on no curve, and not an embedded point.
  for (std::size_t i = 0; i < previous.size(); ++i)
    if (previous.kind[i] == NodeKind::Fixed && previous.curve[i] < 0 &&
        std::find(embedded_.begin(), embedded_.end(), previous.x[i]) == embedded_.end())
      previous.kind[i] = NodeKind::Interior;
}

Mesh LayerMotion::mesh_core(NodeSet& nodes, bool cleanup, const std::function<Mesh(NodeSet&)>& remesh) {
  std::size_t dropped = 0;
  NodeSet core = without_front_nodes(nodes, core_rest_, dropped);
  if (nodes.has_ids()) {
    core.id.clear();
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const int c = nodes.curve[i];
      const bool on_front =
          nodes.kind[i] == NodeKind::Boundary && c >= 0 && core_rest_.curves[static_cast<std::size_t>(c)].fixed_points;
      if (!on_front) core.id.push_back(nodes.id[i]);
    }
  }
  if (dropped > 0)
    progress(layered_->core, "boundary layers: {} node(s) the simulation snapped onto a layer front left out", dropped);
  NodeSet before = core;
  Mesh mesh = remesh(core);
  const std::vector<Vec2> steep = cleanup ? steep_junctions(*layered_, mesh, kSteepJunction) : std::vector<Vec2>{};
  steep_ = steep.size();
  if (!steep.empty() && place_first_row(before, *layered_, &steep) > 0) {
    core = std::move(before);
    mesh = remesh(core);
  }
  nodes = std::move(core);
  return mesh;
}

MotionStep LayerMotion::join(const MeshInputs& core_now, const Mesh& core_mesh, const NodeSet& core_nodes,
                             MotionStepRecord& rec, std::int64_t& next_id) {
  MotionStep out;
  out.mixed = merged_layer_mesh(*inputs_, *layered_, core_now, core_mesh);
  // The join appends each table's nodes that are not on a front, in order: their ids, once.
  if (rec.step == 0)
    for (const LayerSection& s : layered_->sections) {
      const std::vector<char> on_front = front_flags(s.mesh);
      for (const char f : on_front)
        if (!f) layer_ids_.push_back(next_id++);
    }
  const std::size_t n = out.mixed.points.size();
  if (core_nodes.id.size() != core_mesh.points.size() || n != core_mesh.points.size() + layer_ids_.size())
    throw Error(fmt::format("motion: the joined mesh has {} points for {} core nodes and {} layer nodes", n,
                            core_nodes.size(), layer_ids_.size()));
  NodeSet& all = out.nodes;
  all = core_nodes;
  all.curve_nodes.clear();
  all.constraint_curves.clear();
  for (std::size_t i = core_nodes.size(); i < n; ++i) {
    all.add(out.mixed.points[i], 0.0, NodeKind::Fixed, -1);
    all.id.back() = layer_ids_[i - core_nodes.size()];
  }
  PointValues ids{"node_id", 1, {}, true};
  ids.values.assign(all.id.begin(), all.id.end());
  out.mixed.point_data.push_back(ids);
  out.mesh = triangulated(out.mixed);
  out.mesh.point_data.push_back(std::move(ids));
  // The records over every node and cell; min_angle stays the core's.
  rec.nodes = n;
  rec.ids_kept = previous_ids_.empty()
                     ? 1.0
                     : static_cast<double>(ids_kept(previous_ids_, all.id)) / static_cast<double>(previous_ids_.size());
  previous_ids_ = all.id;
  rec.steep_junctions = steep_;
  rec.layer_first_height_within_2pct = 1.0;
  for (const LayerSection& s : layered_->sections) {
    const LayerMeasures m = measure_layers(s.mesh, s.settings.first_height);
    rec.layer_cells += static_cast<std::size_t>(m.cells);
    rec.layer_inverted += static_cast<std::size_t>(m.inverted_cells);
    rec.layer_max_angle = std::max(rec.layer_max_angle, m.max_angle_deg);
    rec.layer_first_height_within_2pct = std::min(rec.layer_first_height_within_2pct, m.first_height_within_2pct);
    rec.layer_growth_max = std::max(rec.layer_growth_max, m.growth_max);
  }
  rec.inverted += rec.layer_inverted;
  out.record = rec;
  return out;
}

void LayerMotion::write_step_files(const CaseConfig& config, const fs::path& dir, const MixedMesh& mixed,
                                   const Mesh& mesh, const MotionStepRecord& rec) {
  fs::create_directories(dir);
  std::vector<std::string> formats{"vtu"};
  for (const std::string& f : config.output.formats)
    if (f != "vtu" && is_mixed_mesh_format(f)) formats.push_back(f);
  write_mixed_mesh(mixed, dir, "mesh", formats, nullptr, wall_curves(config));
  if (!config.output.wants("png")) return;
  MeshPictureOptions picture;
  picture.title = fmt::format("{} - step {} t = {:.4g} ({} cells, {} in the boundary layer)", config.name, rec.step,
                              rec.t, mixed.cells.size(), rec.layer_cells);
  if (!config.output.views.empty()) picture.window = config.output.views.front().window;
  write_mesh_picture(dir / "mesh.png", mesh, picture);
}

}  // namespace pdmesh
