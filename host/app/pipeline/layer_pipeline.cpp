// The boundary-layer run (layer_pipeline.hpp): the layers of every [[boundary_layer]] table, the
// core's case on their fronts, and the merged mesh's outputs.
#include "app/pipeline/layer_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/pipeline/layer_metric.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/pipeline_detail.hpp"
#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "io/quality_report.hpp"
#include "layers/front_geometry.hpp"
#include "layers/layer_measures.hpp"
#include "mesh/metric_quality.hpp"
#include "mesh/quality.hpp"
#include "mesh/region_tags.hpp"
#include "render/mesh_picture.hpp"

namespace pdmesh {

namespace fs = std::filesystem;
using mesh_detail::progress;

namespace {

// The case's field, lowered near the layer fronts to q_i + gradation x distance from each front node
// i, with q_i = growth x the last layer's height there (or the front's mean edge length at i where
// that is shorter): the core's first triangles continue the layer's growth.
class FrontSpacing final : public SpacingField {
 public:
  struct Source {
    Vec2 p;
    double q;
  };
  FrontSpacing(const SpacingField& base, std::vector<Source> sources, double gradation)
      : base_(base), sources_(std::move(sources)), gradation_(gradation) {
    std::sort(sources_.begin(), sources_.end(), [](const Source& a, const Source& b) { return a.p.x < b.p.x; });
  }
  double at(Vec2 p) const override {
    double q = base_.at(p);
    // Sources farther than q / gradation in x cannot lower q: scan outwards from p.x until then.
    const auto mid =
        std::lower_bound(sources_.begin(), sources_.end(), p.x, [](const Source& s, double x) { return s.p.x < x; });
    for (auto it = mid; it != sources_.end() && gradation_ * (it->p.x - p.x) < q; ++it)
      q = std::min(q, it->q + gradation_ * dist(p, it->p));
    for (auto it = mid; it != sources_.begin();) {
      --it;
      if (gradation_ * (p.x - it->p.x) >= q) break;
      q = std::min(q, it->q + gradation_ * dist(p, it->p));
    }
    return q;
  }
  // The core's inputs sample this field into their base tree in large batches (a quadtree's corners):
  // the points are shared out to the cores, each value at()'s whatever the thread (the base field
  // and the sources are only read).
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override {
    q.resize(p.size());
    parallel_for(
        p.size(), [&](std::size_t i) { q[i] = at(p[i]); }, 1024);
  }

 private:
  const SpacingField& base_;
  std::vector<Source> sources_;
  double gradation_;
};

// A ray's last layer height over the wall (its top two nodes' distance along the ray, times the
// ray's correction); 0 for a ray without layers or whose column is merged below the front.
double last_height(const LayerMesh& m, const LayerRay& ray) {
  if (ray.nodes.size() < 2 || ray.merged) return 0.0;
  return ray.correction * dist(m.nodes[static_cast<std::size_t>(ray.nodes.back())],
                               m.nodes[static_cast<std::size_t>(ray.nodes[ray.nodes.size() - 2])]);
}

// The same last layer by its metric length under `metric` (0 where last_height is 0).
double last_metric_length(const LayerMesh& m, const LayerRay& ray, const MetricField& metric) {
  if (ray.nodes.size() < 2 || ray.merged) return 0.0;
  const Vec2 top = m.nodes[static_cast<std::size_t>(ray.nodes.back())];
  const Vec2 below = m.nodes[static_cast<std::size_t>(ray.nodes[ray.nodes.size() - 2])];
  return edge_length(metric.at(below), metric.at(top), top - below);
}

// The core's spacing at a front node is at least this share of the longest front edge at it: where
// collisions thin the layer (30P30N's gaps and cove) or a fan spreads its tops, the last layer is
// several times lower than the front's edges (the wall's node spacing), and a core sized by the
// last layer alone meets those edges with flat triangles.
constexpr double kFrontEdgeShare = 0.8;

// Per layer node: the longest front edge at it (0 off the fronts).
std::vector<double> longest_front_edge(const LayerMesh& m) {
  std::vector<double> longest(m.nodes.size(), 0.0);
  for (std::size_t chain = 0; chain < m.fronts.size(); ++chain) {
    const LayerFront f = core_front(m, chain);
    const std::size_t n = f.nodes.size();
    for (std::size_t k = 0; k + (f.closed ? 0 : 1) < n; ++k) {
      const auto a = static_cast<std::size_t>(f.nodes[k]), b = static_cast<std::size_t>(f.nodes[(k + 1) % n]);
      const double l = dist(m.nodes[a], m.nodes[b]);
      longest[a] = std::max(longest[a], l);
      longest[b] = std::max(longest[b], l);
    }
  }
  return longest;
}

// The layer generator sees the case's spacing times this as the core's: layers stop where the case's
// spacing is below growth x the layer height / this.
constexpr double kCoreStopSlack = 1.5;

// Under a metric field: a ray whose last layer is below 1 / this metric units gets a source of the
// core's graded metric (FrontGradedMetric); above it the core's unit step continues the layer.
constexpr double kGradedJunction = 2.0;
// ... if its layers reached this share of the table's thickness (not stopped by the metric or a
// collision before it).
constexpr double kFullThicknessShare = 0.99;

// With elements = "triangles": the largest tilt (degrees) of a ray from its wall segments' normals
// (LayerSettings::max_ray_tilt_deg), so that the split wall cells stay within about 90 + this.
constexpr double kSplitRayTilt = 5.0;

void append_columns(std::vector<PeriodicColumn>& to, std::vector<PeriodicColumn> more) {
  to.insert(to.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end()));
}

// Every mesh format asked for must hold the layer's quadrilaterals (the pictures' png and svg are no
// mesh formats).
void check_formats(const CaseConfig& config) {
  for (const std::string& f : config.output.formats)
    if (is_mesh_format(f) && !is_mixed_mesh_format(f))
      throw InputError(fmt::format("{}: output.formats: '{}' cannot hold the cells of [[boundary_layer]] ({} can)",
                                   config.source.string(), f, fmt::join(mixed_mesh_format_names(), ", ")));
}

}  // namespace

std::unique_ptr<LayeredCase> build_layers(const CaseConfig& config, const MeshInputs& inputs,
                                          const SpacingStage& spacing) {
  const auto start = std::chrono::steady_clock::now();
  if (config.resume)
    throw InputError(fmt::format("{}: --resume is not supported with [[boundary_layer]]", config.source.string()));
  check_formats(config);
  auto out = std::make_unique<LayeredCase>();
  // The field as asked: the core relaxes at spacing.relax_scale x its own field (FrontSpacing below)
  // as any case does, so that its edges at the fronts come out at the sources' q.
  const SpacingField& field = spacing.asked();
  // The layers stop where the case's spacing is below growth x their layer height / 1.5: the core's
  // field is lowered to growth x the last layer at the fronts anyway, and a core up to 1.5 times
  // finer than the front's spacing still meshes well on it, so a slightly finer case field (a
  // trailing edge's clustered input points) does not cut the layer short of its thickness.
  const CoreSpacing core_spacing = [&field](Vec2 p) { return kCoreStopSlack * field.at(p); };
  // Each table's layers on the geometry the ones before it left: their fronts are curves it stops at.
  std::shared_ptr<const Geometry> geometry(&inputs.geometry, [](const Geometry*) {});
  std::vector<RawCurve> curves;
  GeometryOptions options;
  options.join_tolerance = config.geometry.join_tolerance;
  options.corner_angle_deg = config.geometry.corner_angle;
  std::vector<FrontSpacing::Source> sources;
  // The core's field (and under a metric its metric) grows from the fronts at this rate.
  out->gradation = config.spacing.gradation > 0.0 ? config.spacing.gradation : 0.2;
  // [[periodic]]: each table's transform from the input's curves, for every layer table and the core.
  out->periodic.reserve(config.periodic.size());
  for (const CaseConfig::Periodic& p : config.periodic) {
    const ResolvedPeriodic r = resolve_periodic(p, inputs.geometry);
    out->periodic.push_back({&p, r.transform, r.tolerance});
  }
  for (const CaseConfig::BoundaryLayer& b : config.boundary_layers) {
    LayerSection s;
    s.config = b;
    s.settings.first_height = b.first_height;
    s.settings.growth = b.growth;
    s.settings.thickness = b.thickness;
    s.settings.layers = b.layers;
    s.settings.split_quads = !b.quads;
    // Split wall cells with at most kSplitRayTilt + 90 degrees: their rays within that of their
    // segments' normals, fans where the wall turns more.
    if (s.settings.split_quads) s.settings.max_ray_tilt_deg = kSplitRayTilt;
    s.settings.fan_elements_per_pi = fan_elements_matching_core(b.growth);
    check_layer_settings(s.settings);
    s.walls = curves_by_name(*geometry, b.curves, b.curves_where + ": boundary_layer.curves");
    // The table's thickness where nothing limits it: `thickness`, or that of `layers` layers.
    const double full_thickness =
        b.layers > 0 ? b.first_height * (std::pow(b.growth, b.layers) - 1.0) / (b.growth - 1.0) : b.thickness;
    if (inputs.metric) {
      // Under a metric field the layer follows the metric: wall nodes at about unit metric length
      // along the wall (where its curvature allows; the wall refinement, which splits the wall by
      // the last layer's height, is off) and the thickness stopped by the metric's length along
      // each ray.
      const double offset = full_thickness;
      try {
        geometry = std::make_shared<const Geometry>(
            metric_wall_geometry(*geometry, s.walls, *inputs.tree, *inputs.metric, offset, options));
      } catch (const GeometryError& e) {
        // A chord that meets another curve (a narrow gap): the wall keeps the input's points.
        progress(config, "boundary layers: the wall curves {} keep their input points under the metric ({})",
                 fmt::join(b.curves, ", "), e.what());
      }
      s.walls = curves_by_name(*geometry, b.curves, b.curves_where + ": boundary_layer.curves");
      s.settings.split_span = 0.0;
      s.settings.core_room = 0.0;  // the core is anisotropic: thin rows between fronts are the metric's
      const MetricSizeAlongRay along_ray(*geometry, s.walls, *inputs.metric);
      s.geometry = geometry;
      const PeriodicLayerEnds ends = periodic_layer_ends(out->periodic, *geometry, s.walls, b);
      s.mesh = build_boundary_layers(*geometry, s.walls, s.settings, along_ray, ends.tied);
      append_columns(out->periodic_columns, match_periodic_columns(s.mesh, *geometry, ends, b));
    } else {
      s.geometry = geometry;
      const PeriodicLayerEnds ends = periodic_layer_ends(out->periodic, *geometry, s.walls, b);
      s.mesh = build_boundary_layers(*geometry, s.walls, s.settings, core_spacing, ends.tied);
      append_columns(out->periodic_columns, match_periodic_columns(s.mesh, *geometry, ends, b));
    }
    // Each front node's mean edge length along the front and the longest front edge at it. The core's
    // spacing there is growth x the last layer where the front's edges agree with it; where the front
    // is denser (a trailing edge whose columns could not all merge) it is the mean edge, and where it
    // is sparser (collisions thin the layer in 30P30N's gaps and cove, a fan spreads its tops) at
    // least kFrontEdgeShare x the longest edge, so that the core's triangles on the front are not
    // flat slivers of the layer's size.
    const std::vector<double> longest = longest_front_edge(s.mesh);
    std::map<int, double> front_edge;
    std::map<int, Vec2> front_chord;  // from the front node before to the one after
    for (std::size_t chain = 0; chain < s.mesh.fronts.size(); ++chain) {
      const LayerFront f = core_front(s.mesh, chain);
      const std::size_t n = f.nodes.size();
      for (std::size_t i = 0; i < n; ++i) {
        if (!f.closed && (i == 0 || i + 1 == n)) continue;
        const auto at = [&](std::size_t k) { return s.mesh.nodes[static_cast<std::size_t>(f.nodes[k % n])]; };
        front_edge[f.nodes[i]] = 0.5 * (dist(at(i + n - 1), at(i)) + dist(at(i), at(i + 1)));
        front_chord[f.nodes[i]] = at(i + 1) - at(i + n - 1);
      }
    }
    // Under a metric field: per ray, whether the metric stopped a ray of its chain (then the
    // grading along the wall lowers that ray's neighbours below their own stop, and only rays that
    // reached the thickness are sources; a chain the metric stops nowhere has its cut rays cut by
    // collisions, which are sources too).
    std::vector<char> chain_stopped(s.mesh.rays.size(), 0);
    for (std::size_t c = 0; c + 1 < s.mesh.chain_ray_begin.size(); ++c) {
      const auto begin = static_cast<std::size_t>(s.mesh.chain_ray_begin[c]);
      const auto end = static_cast<std::size_t>(s.mesh.chain_ray_begin[c + 1]);
      const bool stopped = std::any_of(s.mesh.rays.begin() + static_cast<std::ptrdiff_t>(begin),
                                       s.mesh.rays.begin() + static_cast<std::ptrdiff_t>(end), [&](const LayerRay& r) {
                                         return r.free_thickness < kFullThicknessShare * full_thickness;
                                       });
      std::fill(chain_stopped.begin() + static_cast<std::ptrdiff_t>(begin),
                chain_stopped.begin() + static_cast<std::ptrdiff_t>(end), stopped ? 1 : 0);
    }
    for (std::size_t r = 0; r < s.mesh.rays.size(); ++r)
      if (const double h = last_height(s.mesh, s.mesh.rays[r]); h > 0.0) {
        const LayerRay& ray = s.mesh.rays[r];
        const auto top = static_cast<std::size_t>(ray.nodes.back());
        double q = b.growth * h;
        const auto e = front_edge.find(ray.nodes.back());
        if (e != front_edge.end()) q = std::min(q, e->second);
        q = std::max(q, kFrontEdgeShare * longest[top]);
        // A node spacing at the front for the relaxation, which runs at relax_scale x the core's
        // field: divided by it, the core's first rows relax at q as they did at relax_scale 1 (the
        // junction's limits were measured so).
        sources.push_back({s.mesh.nodes[top], q / spacing.relax_scale()});
        const bool full = ray.thickness >= kFullThicknessShare * full_thickness;
        const bool cut = ray.free_thickness >= kFullThicknessShare * full_thickness && chain_stopped[r] == 0;
        if (inputs.metric && (full || cut) && kGradedJunction * last_metric_length(s.mesh, ray, *inputs.metric) < 1.0) {
          // A ray whose layers reached the table's thickness (which is the user's: it is kept), or
          // on a chain the metric stops nowhere, cut below it by a collision (a slot between two
          // elements, far narrower than the metric's unit), with a last layer so far below the
          // metric's unit along it that the step into a core of unit length would be above
          // kGradedJunction last layers: the core's metric continues the layer's growth from its
          // last layer across the front, and at a fan's top has the fan's front edges along it.
          // Across the front is the normal of the chord through its neighbours (towards the core):
          // both front edges at the top are as near to along the front as they can be, which a
          // metric as thin as the last layer needs (the ray's direction can be a few degrees off
          // it); the ray where the front ends. A ray the metric stopped has its last layer at 1 / growth to 1 unit
          // already; its neighbours lowered by the grading are left out (under the Hessian cases' strongly anisotropic
          // band the slab across their front shrinks the metric along the wall).
          const Vec2 below = s.mesh.nodes[static_cast<std::size_t>(ray.nodes[ray.nodes.size() - 2])];
          const double last = dist(s.mesh.nodes[top], below);
          Vec2 u = (s.mesh.nodes[top] - below) * (1.0 / last);
          if (const auto c = front_chord.find(ray.nodes.back()); c != front_chord.end() && norm(c->second) > 0.0) {
            const Vec2 normal = Vec2{-c->second.y, c->second.x} * (1.0 / norm(c->second));
            u = dot(normal, u) >= 0.0 ? normal : normal * -1.0;
          }
          out->front_metric.push_back({s.mesh.nodes[top], u, b.growth * last, ray.fan ? longest[top] : 0.0});
        }
      }
    // An open chain's end column inside the domain (its end ray off the curve that continues the
    // boundary) is part of the front from the wall node up: its edges are the layers' heights, from
    // h1 at the wall, and the core meets them at their length (else a core node fans out to the
    // column's dense nodes in slivers).
    std::set<int> tops;
    for (const LayerRay& ray : s.mesh.rays) tops.insert(ray.nodes.back());
    for (std::size_t chain = 0; chain < s.mesh.fronts.size(); ++chain) {
      const LayerFront f = core_front(s.mesh, chain);
      if (f.closed) continue;
      const std::size_t n = f.nodes.size();
      for (std::size_t i = 0; i < n; ++i) {
        if (tops.count(f.nodes[i]) > 0) continue;
        const Vec2 p = s.mesh.nodes[static_cast<std::size_t>(f.nodes[i])];
        double sum = 0.0;
        int edges = 0;
        for (const std::size_t j : {i - 1, i + 1})
          if (j < n) {  // i - 1 wraps past n at i = 0
            sum += dist(p, s.mesh.nodes[static_cast<std::size_t>(f.nodes[j])]);
            ++edges;
          }
        if (edges > 0) sources.push_back({p, sum / edges / spacing.relax_scale()});
      }
    }
    curves = front_curves(*geometry, s.walls, s.mesh);
    // front_curves puts the fronts last, one per chain.
    for (std::size_t k = curves.size() - s.mesh.fronts.size(); k < curves.size(); ++k)
      out->fronts.insert(curves[k].name);
    geometry = std::make_shared<const Geometry>(build_geometry(curves, options));
    out->sections.push_back(std::move(s));
  }
  // The core: the fronts are polylines of layer nodes in the meshing plane (the caller hands the core
  // the case's projection for its outputs), its base field the case's lowered at the fronts.
  out->core = mesh_detail::core_case_on_curves(
      config, std::move(curves), std::make_shared<FrontSpacing>(field, std::move(sources), out->gradation));
  out->core.boundary_layers.clear();
  // The core's periodic curves start at the layers' tops: an inferred translation stays the one the
  // layers were tied by (inferred from the input's curves), not one inferred again from the trimmed ones.
  for (std::size_t k = 0; k < out->periodic.size(); ++k) {
    CaseConfig::Periodic& p = out->core.periodic[k];
    if (p.kind != CaseConfig::Periodic::Kind::Infer) continue;
    p.kind = CaseConfig::Periodic::Kind::Translate;
    p.translate = {out->periodic[k].transform.shift.x, out->periodic[k].transform.shift.y};
    p.inferred = true;
  }
  out->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::size_t cells = 0;
  for (const LayerSection& s : out->sections) cells += s.mesh.cells.size();
  progress(config, "boundary layers: {} table(s), {} cells, {:.3f} s; the core is meshed on their fronts",
           out->sections.size(), cells, out->seconds);
  return out;
}

std::unique_ptr<MeshInputs> layered_core_inputs(const LayeredCase& layered, const MeshInputs& inputs) {
  auto core = std::make_unique<MeshInputs>(layered.core);
  // The core's spacing is its case's given field (FrontSpacing), which does not refer to the metric
  // replaced here.
  if (inputs.metric)
    core->metric = std::make_unique<FrontGradedMetric>(*inputs.metric, layered.front_metric, layered.gradation);
  return core;
}

NodeSet without_front_nodes(const NodeSet& nodes, const Geometry& core_geometry, std::size_t& dropped) {
  std::vector<int> index(nodes.size(), -1);
  NodeSet out;
  dropped = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const int c = nodes.curve[i];
    if (nodes.kind[i] == NodeKind::Boundary && c >= 0 &&
        core_geometry.curves[static_cast<std::size_t>(c)].fixed_points) {
      ++dropped;
      continue;
    }
    index[i] = out.add(nodes.x[i], nodes.q[i], nodes.kind[i], c);
  }
  out.curve_nodes.resize(nodes.curve_nodes.size());
  for (std::size_t c = 0; c < nodes.curve_nodes.size(); ++c)
    for (const int n : nodes.curve_nodes[c])
      if (index[static_cast<std::size_t>(n)] >= 0) out.curve_nodes[c].push_back(index[static_cast<std::size_t>(n)]);
  return out;
}

namespace {

// A first-row target takes the nearest interior node within this share of its step (growth x the
// last layer along the ray), and is left empty within this share of a front node other than its top
// or of a target already taken (concave fronts, collisions, fans).
constexpr double kClaimShare = 1.25;
constexpr double kTargetClearance = 0.6;
// Only where the front's edges at the top are at most this many steps (growth x the last layer)
// long; the target is lifted where they are longer than kEdgeOverStep steps, by at most kMaxLift
// (a junction growth of 1.2 x 1.2 = 1.44 at g = 1.2).
constexpr double kMaxEdgeOverStep = 1.5;
constexpr double kEdgeOverStep = 1.2;
constexpr double kMaxLift = 1.2;

// Indices of `points` sorted by x, and the ones within `r` of p (by a scan of that x band).
struct XIndex {
  explicit XIndex(const std::vector<Vec2>& points) : pts(points), order(points.size()) {
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return pts[a].x < pts[b].x; });
  }
  template <class F>
  void near(Vec2 p, double r, F&& f) const {
    auto it =
        std::lower_bound(order.begin(), order.end(), p.x - r, [&](std::size_t i, double x) { return pts[i].x < x; });
    for (; it != order.end() && pts[*it].x <= p.x + r; ++it)
      if (const double d = dist(pts[*it], p); d <= r) f(*it, d);
  }
  const std::vector<Vec2>& pts;
  std::vector<std::size_t> order;
};

}  // namespace

std::vector<Vec2> steep_junctions(const LayeredCase& layered, const Mesh& core, double limit) {
  std::map<std::pair<double, double>, int> at;
  for (std::size_t i = 0; i < core.points.size(); ++i)
    at.emplace(std::make_pair(core.points[i].x, core.points[i].y), static_cast<int>(i));
  std::vector<std::vector<int>> neighbours(core.points.size());
  for (const auto& t : core.triangles)
    for (int i = 0; i < 3; ++i) {
      const int a = t[static_cast<std::size_t>(i)], b = t[static_cast<std::size_t>((i + 1) % 3)];
      neighbours[static_cast<std::size_t>(a)].push_back(b);
      neighbours[static_cast<std::size_t>(b)].push_back(a);
    }
  std::vector<Vec2> steep;
  for (const LayerSection& s : layered.sections)
    for (const LayerRay& ray : s.mesh.rays) {
      if (ray.nodes.size() < 2 || ray.merged) continue;
      const Vec2 top = s.mesh.nodes[static_cast<std::size_t>(ray.nodes.back())];
      const Vec2 below = s.mesh.nodes[static_cast<std::size_t>(ray.nodes[ray.nodes.size() - 2])];
      const auto it = at.find({top.x, top.y});
      if (it == at.end()) continue;
      const double h = dist(top, below);
      const Vec2 u = (top - below) * (1.0 / h);
      // The core neighbour most in line with the ray (within acos 0.7, as the column walks of
      // tools/eval do), and how far up the ray it lies.
      double best_cos = 0.7, rise = 0.0;
      for (const int v : neighbours[static_cast<std::size_t>(it->second)]) {
        const Vec2 d = core.points[static_cast<std::size_t>(v)] - top;
        const double l = std::hypot(d.x, d.y), along = d.x * u.x + d.y * u.y;
        if (l > 0.0 && along / l > best_cos) best_cos = along / l, rise = along;
      }
      if (rise > limit * h) steep.push_back(top);
    }
  return steep;
}

std::size_t place_first_row(NodeSet& nodes, const LayeredCase& layered, const std::vector<Vec2>* only) {
  std::map<std::pair<double, double>, bool> wanted;
  if (only != nullptr)
    for (const Vec2& p : *only) wanted[{p.x, p.y}] = true;
  struct Target {
    Vec2 p;
    Vec2 top;
    double step;
  };
  std::vector<Target> targets;
  for (const LayerSection& s : layered.sections) {
    const std::vector<double> longest = longest_front_edge(s.mesh);
    for (const LayerRay& ray : s.mesh.rays) {
      if (ray.nodes.size() < 2 || ray.merged) continue;
      const auto top_node = static_cast<std::size_t>(ray.nodes.back());
      const Vec2 top = s.mesh.nodes[top_node];
      if (only != nullptr && wanted.count({top.x, top.y}) == 0) continue;
      const Vec2 below = s.mesh.nodes[static_cast<std::size_t>(ray.nodes[ray.nodes.size() - 2])];
      const double plain = s.settings.growth * dist(top, below);
      // Where the front's edges are longer than the step, the target is lifted (by at most
      // kMaxLift) so that the triangles between the pinned nodes and the front are not flat.
      const double lift = std::clamp(longest[top_node] / (kEdgeOverStep * plain), 1.0, kMaxLift);
      const Vec2 step = (top - below) * (s.settings.growth * lift);
      const double length = plain * lift;
      // Front edges much longer than the step: a pinned node there would make flat triangles.
      if (longest[top_node] > kMaxEdgeOverStep * plain) continue;
      targets.push_back({top + step, top, length});
    }
  }
  const XIndex index(nodes.x);
  std::vector<Vec2> kept_at;
  std::vector<double> kept_step;
  struct Pair {
    double d;
    std::size_t target, node;
  };
  std::vector<Pair> pairs;
  for (std::size_t k = 0; k < targets.size(); ++k) {
    const Target& t = targets[k];
    const double clear = kTargetClearance * t.step;
    bool blocked = false;
    std::vector<Pair> mine;
    index.near(t.p, std::max(clear, kClaimShare * t.step), [&](std::size_t i, double d) {
      if (nodes.kind[i] != NodeKind::Interior) {
        if (d < clear && dist(nodes.x[i], t.top) > 0.0) blocked = true;
      } else if (d <= kClaimShare * t.step) {
        mine.push_back({d, k, i});
      }
    });
    if (blocked) continue;
    // Targets of neighbouring rays that crowd each other (a concave front): the first one stays.
    for (std::size_t j = 0; j < kept_at.size() && !blocked; ++j)
      blocked = dist(kept_at[j], t.p) < kTargetClearance * std::min(t.step, kept_step[j]);
    if (blocked) continue;
    kept_at.push_back(t.p);
    kept_step.push_back(t.step);
    pairs.insert(pairs.end(), mine.begin(), mine.end());
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.d < b.d; });
  std::vector<char> filled(targets.size(), 0), claimed(nodes.size(), 0);
  std::size_t moved = 0;
  for (const Pair& p : pairs) {
    if (filled[p.target] || claimed[p.node]) continue;
    filled[p.target] = claimed[p.node] = 1;
    nodes.x[p.node] = targets[p.target].p;
    nodes.kind[p.node] = NodeKind::Fixed;  // the cleanup's smoothing and collapses leave it there
    ++moved;
  }
  return moved;
}

Mesh mesh_layered_core(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
                       const NodeSet& nodes, const LayeredCase& layered, RunPhases* phases, const Mesh* triangulated) {
  CaseConfig core = config;
  core.write_outputs = false;
  std::size_t dropped = 0;
  NodeSet core_nodes = without_front_nodes(nodes, inputs.geometry, dropped);
  if (dropped > 0)
    progress(config, "boundary layers: {} node(s) the simulation snapped onto a layer front left out", dropped);
  Mesh mesh = mesh_and_measure(core, inputs, spacing, core_nodes, phases, dropped ? nullptr : triangulated);
  // Only with the cleanup, which makes the triangles around a moved node good again, and not under a
  // metric field: there the core's first row follows the metric, whose unit step along a ray is not
  // growth x the last layer (the layer stops where it reaches it).
  const std::vector<Vec2> steep = config.cleanup.enabled && spacing.metric() == nullptr
                                      ? steep_junctions(layered, mesh, kSteepJunction)
                                      : std::vector<Vec2>{};
  if (!steep.empty()) {
    const std::size_t moved = place_first_row(core_nodes, layered, &steep);
    progress(config, "boundary layers: {} steep junction(s), {} core node(s) pinned on their rays", steep.size(),
             moved);
    if (moved > 0) mesh = mesh_and_measure(core, inputs, spacing, core_nodes, phases, nullptr);
  }
  return mesh;
}

namespace {

// The layer cells and the core triangles in one mesh; the core's points first, each front node of
// the layers mapped onto the core's point at exactly its place.
MixedMesh merge(const MeshInputs& inputs, const LayeredCase& layered, const MeshInputs& core_inputs, const Mesh& core) {
  MixedMesh m;
  m.points = core.points;
  m.curve_names = inputs.curve_names();
  const auto original = [&](const std::string& name) {
    const auto it = std::find(m.curve_names.begin(), m.curve_names.end(), name);
    if (it == m.curve_names.end()) throw Error(fmt::format("boundary layer: curve '{}' not in the input", name));
    return static_cast<int>(it - m.curve_names.begin());
  };
  for (const auto& t : core.triangles) {
    m.cells.push_back({t[0], t[1], t[2], -1});
    m.layer.push_back(0);
  }
  for (const BoundaryEdge& e : core.boundary_edges) {
    const Curve& c = core_inputs.geometry.curves[static_cast<std::size_t>(e.curve)];
    if (layered.is_front(c)) continue;  // inside the merged mesh
    m.boundary_edges.push_back({e.a, e.b, original(c.name)});
  }
  std::map<std::pair<double, double>, int> at;
  for (std::size_t i = 0; i < core.points.size(); ++i)
    at.emplace(std::make_pair(core.points[i].x, core.points[i].y), i);
  for (const LayerSection& s : layered.sections) {
    const LayerMesh& lm = s.mesh;
    std::vector<int> index(lm.nodes.size(), -1);
    for (std::size_t chain = 0; chain < lm.fronts.size(); ++chain)
      for (const int n : core_front(lm, chain).nodes) {
        const Vec2 p = lm.nodes[static_cast<std::size_t>(n)];
        const auto it = at.find({p.x, p.y});
        if (it == at.end())
          throw Error(fmt::format("boundary layer: front node ({}, {}) is not a node of the core mesh", p.x, p.y));
        index[static_cast<std::size_t>(n)] = it->second;
      }
    for (std::size_t i = 0; i < lm.nodes.size(); ++i)
      if (index[i] < 0) {
        index[i] = static_cast<int>(m.points.size());
        m.points.push_back(lm.nodes[i]);
      }
    for (const LayerCell& c : lm.cells) {
      std::array<int, 4> v{-1, -1, -1, -1};
      for (int k = 0; k < (c.triangle() ? 3 : 4); ++k)
        v[static_cast<std::size_t>(k)] = index[static_cast<std::size_t>(c.v[static_cast<std::size_t>(k)])];
      m.cells.push_back(v);
      m.layer.push_back(1);
    }
    // The wall edges: consecutive wall nodes of each chain's rays (a fan's rays share one).
    for (std::size_t chain = 0; chain + 1 < lm.chain_ray_begin.size(); ++chain) {
      const int begin = lm.chain_ray_begin[chain], end = lm.chain_ray_begin[chain + 1];
      const bool closed = lm.chain_closed[chain] != 0;
      for (int r = begin; r < end; ++r) {
        const int next = r + 1 < end ? r + 1 : (closed ? begin : -1);
        if (next < 0) break;
        const LayerRay& a = lm.rays[static_cast<std::size_t>(r)];
        const LayerRay& b = lm.rays[static_cast<std::size_t>(next)];
        if (a.wall_node == b.wall_node) continue;
        const std::string& name = s.geometry->curves[static_cast<std::size_t>(b.curve)].name;
        m.boundary_edges.push_back({index[static_cast<std::size_t>(a.wall_node)],
                                    index[static_cast<std::size_t>(b.wall_node)], original(name)});
      }
      // An open chain's end ray along the curve that continues the boundary: its column is that
      // curve's from the wall node to the top (the core's copy of the curve starts at the top).
      if (closed || end <= begin) continue;
      for (const int r : {begin, end - 1}) {
        const LayerRay& ray = lm.rays[static_cast<std::size_t>(r)];
        if (ray.slide_segment < 0) continue;
        const Segment& seg = s.geometry->segments[static_cast<std::size_t>(ray.slide_segment)];
        const int curve = original(s.geometry->curves[static_cast<std::size_t>(seg.curve)].name);
        for (std::size_t j = 0; j + 1 < ray.nodes.size(); ++j)
          m.boundary_edges.push_back({index[static_cast<std::size_t>(ray.nodes[j])],
                                      index[static_cast<std::size_t>(ray.nodes[j + 1])], curve});
      }
    }
  }
  // The input's physical groups on the merged mesh's curves (its curve names are the input's).
  m.curve_groups = curve_groups_of(inputs.geometry.groups, m.curve_names);
  // The geometry's regions, flooded over the merged cells (each quad as its two triangles) across the
  // edges on no curve of the input: the fronts are no input curves, so a layer cell lies in the region
  // of the core it grows into.
  if (!inputs.geometry.regions.empty()) {
    const std::vector<double> per_triangle =
        region_tags(triangulated(m), inputs.geometry.regions, inputs.node_geometry());
    m.region.reserve(m.cells.size());
    std::size_t t = 0;
    for (const auto& c : m.cells) {
      m.region.push_back(per_triangle[t]);
      t += c[3] < 0 ? 1 : 2;
    }
    m.region_names = region_names_of(inputs.geometry.regions);
  }
  return m;
}

// Growth across the junction: for each front edge, the height of the core triangle on it over the
// mean last layer height of its two nodes' rays. Under a metric field (`metric` not null) both in the
// metric: the last layer's metric length along its ray, and the triangle's height in the metric at the
// edge's midpoint (twice its metric area over the edge's metric length).
std::vector<double> junction_growth(const LayeredCase& layered, const Mesh& core, const MetricField* metric) {
  std::map<std::pair<double, double>, double> last;  // top node -> last layer height
  for (const LayerSection& s : layered.sections)
    for (const LayerRay& ray : s.mesh.rays)
      if (const double h = last_height(s.mesh, ray); h > 0.0) {
        const Vec2 p = s.mesh.nodes[static_cast<std::size_t>(ray.nodes.back())];
        last[{p.x, p.y}] = metric != nullptr ? last_metric_length(s.mesh, ray, *metric) : h;
      }
  std::vector<double> ratios;
  for (const auto& t : core.triangles)
    for (int i = 0; i < 3; ++i) {
      const Vec2 a = core.points[static_cast<std::size_t>(t[static_cast<std::size_t>(i)])];
      const Vec2 b = core.points[static_cast<std::size_t>(t[static_cast<std::size_t>((i + 1) % 3)])];
      const Vec2 c = core.points[static_cast<std::size_t>(t[static_cast<std::size_t>((i + 2) % 3)])];
      const auto ha = last.find({a.x, a.y}), hb = last.find({b.x, b.y});
      if (ha == last.end() || hb == last.end()) continue;
      // Only edges of the front: both nodes consecutive on it is not known here, so the edge must
      // be a boundary edge of the core (its other side is the layer).
      double height = std::fabs(cross(b - a, c - a)) / dist(a, b);
      if (metric != nullptr) {
        const Metric m = metric->at((a + b) * 0.5);
        const double det = m.m11 * m.m22 - m.m12 * m.m12;
        height = std::fabs(cross(b - a, c - a)) * std::sqrt(det) / m.length(b - a);
      }
      ratios.push_back(height / (0.5 * (ha->second + hb->second)));
    }
  return ratios;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(
      std::min<double>(static_cast<double>(v.size()) - 1, q * static_cast<double>(v.size())))];
}

// The core triangles with an edge on the front (a core boundary edge on a front curve, whose nodes
// are layer tops): the junction is measured on them only.
Mesh front_triangles(const LayeredCase& layered, const MeshInputs& core_inputs, const Mesh& core_mesh) {
  Mesh front_only = core_mesh;
  std::map<std::pair<int, int>, bool> front_edge;
  for (const BoundaryEdge& e : core_mesh.boundary_edges)
    if (layered.is_front(core_inputs.geometry.curves[static_cast<std::size_t>(e.curve)]))
      front_edge[{std::min(e.a, e.b), std::max(e.a, e.b)}] = true;
  front_only.triangles.clear();
  for (const auto& t : core_mesh.triangles) {
    bool on = false;
    for (int i = 0; i < 3; ++i) {
      const int a = t[static_cast<std::size_t>(i)], b = t[static_cast<std::size_t>((i + 1) % 3)];
      on = on || front_edge.count({std::min(a, b), std::max(a, b)}) > 0;
    }
    if (on) front_only.triangles.push_back(t);
  }
  return front_only;
}

// Under a metric field: how the layers' fronts sit in the case's metric. The front edges (the core's
// boundary edges on a front) by their metric length against the unit-mesh window, and each front
// node's last layer (its top two nodes along the ray) by its metric length, which a layer that
// continues into a unit mesh of the metric has at about 1 / growth.
struct FrontInMetric {
  std::size_t edges = 0;
  double window_percent = 0.0;
  double length_min = 0.0, length_median = 0.0, length_max = 0.0;
  std::size_t rays = 0;
  double last_min = 0.0, last_median = 0.0, last_max = 0.0;
};

FrontInMetric front_in_metric(const LayeredCase& layered, const MeshInputs& core_inputs, const Mesh& core_mesh,
                              const MetricField& metric) {
  FrontInMetric f;
  std::vector<double> lengths;
  for (const BoundaryEdge& e : core_mesh.boundary_edges) {
    if (!layered.is_front(core_inputs.geometry.curves[static_cast<std::size_t>(e.curve)])) continue;
    const Vec2 a = core_mesh.points[static_cast<std::size_t>(e.a)], b = core_mesh.points[static_cast<std::size_t>(e.b)];
    lengths.push_back(edge_length(metric.at(a), metric.at(b), b - a));
  }
  f.edges = lengths.size();
  if (!lengths.empty()) {
    const auto in = std::count_if(lengths.begin(), lengths.end(),
                                  [](double l) { return l >= kMetricWindowLo && l <= kMetricWindowHi; });
    f.window_percent = 100.0 * static_cast<double>(in) / static_cast<double>(lengths.size());
    f.length_min = *std::min_element(lengths.begin(), lengths.end());
    f.length_max = *std::max_element(lengths.begin(), lengths.end());
    f.length_median = quantile(lengths, 0.5);
  }
  std::vector<double> last;
  for (const LayerSection& s : layered.sections)
    for (const LayerRay& ray : s.mesh.rays)
      if (ray.nodes.size() >= 2 && !ray.merged) last.push_back(last_metric_length(s.mesh, ray, metric));
  f.rays = last.size();
  if (!last.empty()) {
    f.last_min = *std::min_element(last.begin(), last.end());
    f.last_max = *std::max_element(last.begin(), last.end());
    f.last_median = quantile(last, 0.5);
  }
  return f;
}

// The mixed mesh in the mesh-file formats the case asks for; returns the files written.
std::vector<fs::path> write_layered_mesh_files(const CaseConfig& config, const MeshInputs& inputs,
                                               const MixedMesh& mixed, RunPhases& phases,
                                               const std::vector<PeriodicLink>& periodic) {
  std::vector<std::string> formats;
  for (const std::string& f : config.output.formats)
    if (is_mixed_mesh_format(f)) formats.push_back(f);
  const auto writer_timer = phases.phase("mesh files");
  // geometry.projection: the files get lon/lat, like the triangle meshes' (mesh_outputs.cpp).
  MixedMesh lonlat;
  if (inputs.projection) {
    lonlat = mixed;
    inputs.projection->inverse(lonlat.points);
  }
  return write_mixed_mesh(inputs.projection ? lonlat : mixed, config.out_dir, "mesh", formats, &periodic,
                          wall_curves(config));
}

}  // namespace

MixedMesh merged_layer_mesh(const MeshInputs& inputs, const LayeredCase& layered, const MeshInputs& core_inputs,
                            const Mesh& core_mesh) {
  return merge(inputs, layered, core_inputs, core_mesh);
}

void write_layered_outputs(const CaseConfig& config, const MeshInputs& inputs, const LayeredCase& layered,
                           const MeshInputs& core_inputs, const Mesh& core_mesh, RunPhases& phases) {
  auto timer = phases.phase("merge layers");
  const MixedMesh mixed = merge(inputs, layered, core_inputs, core_mesh);
  // [[periodic]]: the core's pairs and the layers' end columns, found in the merged mesh.
  const std::vector<PeriodicLink> periodic =
      link_periodic_nodes(boundary_of(mixed), merged_periodic_pairs(mixed, layered.periodic_columns, core_inputs));
  // The pictures (the quads drawn split) are drawn on the background thread while the quality is
  // measured and the files are written; `drawn` stays alive until the wait below (also when something
  // throws).
  // output.color_by = region fills the cells as the mesh files' surfaces (the core's regions, or
  // "domain", and "boundary_layer"); a quality metric is not drawn on the cells of a mixed mesh.
  const bool by_region = config.output.color_by == "region";
  Mesh drawn = config.output.wants("png") ? triangulated(mixed) : Mesh{};
  if (by_region && config.output.wants("png")) add_layer_regions(mixed, drawn);
  timer.stop();
  const PictureGuard guard(phases);
  MeshPictureOptions picture;
  picture.title = fmt::format("{} - mesh ({} cells, {} in the boundary layer)", config.name, mixed.cells.size(),
                              mixed.cells.size() - core_mesh.triangles.size());
  picture.fill_regions = by_region;
  const std::vector<std::string> pictures = mesh_detail::queue_mesh_views(config, drawn, picture, phases);
  timer = phases.phase("quality");
  QualitySummary core_summary = summarize_quality(core_mesh);
  core_summary.points = core_mesh.points.size();
  // Under a metric field the core is measured in the metric it was meshed in (the `metric` section
  // of a metric run, over the core's triangles): the case's, graded down to the layers at the fronts
  // (layered_core_inputs). The fronts and the junction are measured in the case's metric; the core's
  // angles are those of an anisotropic mesh in physical space.
  const MetricField* metric = inputs.metric.get();
  FrontInMetric front;
  if (metric != nullptr) {
    core_summary.has_metric = true;
    core_summary.metric = metric_quality(core_mesh, core_inputs.metric ? *core_inputs.metric : *metric);
    front = front_in_metric(layered, core_inputs, core_mesh, *metric);
  }
  const std::vector<double> junction =
      junction_growth(layered, front_triangles(layered, core_inputs, core_mesh), metric);
  std::string table = format_quality_table(
      core_summary, config.name + (metric != nullptr ? " core (angles in physical space)" : " core"));
  std::string json_layers;
  for (std::size_t k = 0; k < layered.sections.size(); ++k) {
    const LayerSection& s = layered.sections[k];
    const LayerMeasures lm = measure_layers(s.mesh, s.settings.first_height);
    std::vector<std::string> names;
    for (const Curve& c : s.geometry->curves) names.push_back(c.name);
    table += fmt::format("boundary layer {} ({}; h1 {:.4g}, growth {}, {}):\n{}", k + 1,
                         fmt::join(s.config.curves, ", "), s.settings.first_height, s.settings.growth,
                         s.config.quads ? "quads" : "triangles", format_layer_measures(lm, names));
    std::string fans;
    for (const int f : lm.fan_sizes) fans += (fans.empty() ? "" : ", ") + std::to_string(f);
    // Rays below the table's thickness, by what stopped them: the core's spacing (or an end ray's
    // segment) before any collision, a collision (or a repair round) below that; and those left with
    // no layer or one. Merged columns count as their neighbours do (they end below the front).
    const double full =
        s.config.layers > 0
            ? s.config.first_height * (std::pow(s.config.growth, s.config.layers) - 1.0) / (s.config.growth - 1.0)
            : s.config.thickness;
    std::size_t by_core = 0, by_collision = 0, few_layers = 0;
    for (const LayerRay& ray : s.mesh.rays) {
      if (ray.free_thickness < kFullThicknessShare * full)
        ++by_core;
      else if (ray.thickness < kFullThicknessShare * full)
        ++by_collision;
      if (!ray.merged && ray.nodes.size() <= 2) ++few_layers;
    }
    // JSON has no infinity: a ray without layer beside one with layers makes the jump infinite.
    const std::string jump = std::isfinite(lm.max_thickness_jump) ? fmt::format("{}", lm.max_thickness_jump) : "null";
    json_layers += fmt::format(
        "{}      {{\"curves\": [\"{}\"], \"first_height\": {}, \"growth\": {}, \"cells\": {}, \"quads\": {}, "
        "\"triangles\": {}, \"wall_cells\": {}, \"first_height_within_2pct\": {}, \"first_height_max_error\": {}, "
        "\"growth_median\": {}, \"growth_p95\": {}, \"growth_max\": {}, \"max_angle\": {}, \"angles_above_150\": {}, "
        "\"inverted_cells\": {}, \"fan_sizes\": [{}], \"max_thickness_jump\": {}, \"min_thickness\": {}, "
        "\"max_thickness\": {}, \"max_layers\": {}, \"rays\": {}, \"rays_stopped_by_core_spacing\": {}, "
        "\"rays_cut_by_collision\": {}, \"rays_with_at_most_one_layer\": {}}}",
        k ? ",\n" : "", fmt::join(s.config.curves, "\", \""), s.settings.first_height, s.settings.growth, lm.cells,
        lm.quads, lm.triangles, lm.wall_cells, lm.first_height_within_2pct, lm.first_height_max_error, lm.growth_median,
        lm.growth_p95, lm.growth_max, lm.max_angle_deg, lm.angles_above_150, lm.inverted_cells, fans, jump,
        lm.min_thickness, lm.max_thickness, lm.max_layers, s.mesh.rays.size(), by_core, by_collision, few_layers);
  }
  const double j50 = quantile(junction, 0.5), j95 = quantile(junction, 0.95);
  const double jmax = junction.empty() ? 0.0 : *std::max_element(junction.begin(), junction.end());
  table += fmt::format(
      "junction (core triangle height on a front edge / last layer height{}), {} edges: median {:.3f}, "
      "p95 {:.3f}, max {:.3f}\nmerged mesh: {} points, {} cells ({} quads)\n",
      metric != nullptr ? ", both in the metric" : "", junction.size(), j50, j95, jmax, mixed.points.size(),
      mixed.cells.size(), mixed.quads());
  std::string json_front;
  if (metric != nullptr) {
    table += fmt::format(
        "fronts in the metric: {} edges, {:.1f} % in [1/sqrt2, sqrt2], length min {:.3g} median {:.3g} max "
        "{:.3g}; last layer along its ray ({} rays): min {:.3g} median {:.3g} max {:.3g}\n",
        front.edges, front.window_percent, front.length_min, front.length_median, front.length_max, front.rays,
        front.last_min, front.last_median, front.last_max);
    json_front = fmt::format(
        "    \"front_in_metric\": {{\"edges\": {}, \"window_percent\": {}, \"length_min\": {}, "
        "\"length_median\": {}, \"length_max\": {}, \"rays\": {}, \"last_layer_min\": {}, "
        "\"last_layer_median\": {}, \"last_layer_max\": {}}},\n",
        front.edges, front.window_percent, front.length_min, front.length_median, front.length_max, front.rays,
        front.last_min, front.last_median, front.last_max);
  }
  timer.stop();
  if (!config.quiet) fmt::print("{}", table);
  {
    const auto json_timer = phases.phase("quality.json");
    // Under a metric the core's isotropic min angle says nothing about how it honours the metric (its
    // `metric` section does): `core_min_angle` is null there, the angle kept as core_min_angle_physical.
    const std::string angle = metric != nullptr
                                  ? fmt::format("null,\n    \"core_min_angle_physical\": {}", core_summary.min_angle)
                                  : fmt::format("{}", core_summary.min_angle);
    write_quality_json(
        core_summary, config.out_dir, config.name, "", periodic_json(mixed.curve_names, periodic),
        fmt::format(",\n  \"boundary_layer\": {{\n    \"tables\": [\n{}\n    ],\n    \"junction\": {{\"edges\": {}, "
                    "\"median\": {}, \"p95\": {}, \"max\": {}}},\n{}    \"core_min_angle\": {},\n    "
                    "\"points\": {}, \"cells\": {}, \"quads\": {}\n  }}\n",
                    json_layers, junction.size(), j50, j95, jmax, json_front, angle, mixed.points.size(),
                    mixed.cells.size(), mixed.quads()));
  }
  for (const PeriodicLink& l : periodic)
    progress(config, "periodic: '{}' -> '{}': {} node pairs, largest mismatch {:.3g}",
             mixed.curve_names[static_cast<std::size_t>(l.source_curve)],
             mixed.curve_names[static_cast<std::size_t>(l.curve)], l.nodes.size(), l.max_mismatch);
  const std::vector<fs::path> written = write_layered_mesh_files(config, inputs, mixed, phases, periodic);
  {
    const auto wait_timer = phases.phase("waiting for pictures");
    phases.wait_pictures();
  }
  std::string names;
  for (const std::string& name : written_names(config.out_dir, written)) names += ", " + name;
  for (const auto& p : pictures) names += ", " + p;
  progress(config, "mesh: {} cells ({} core triangles, {} layer cells); wrote {}/quality.json{}", mixed.cells.size(),
           core_mesh.triangles.size(), mixed.cells.size() - core_mesh.triangles.size(), config.out_dir.string(), names);
}

}  // namespace pdmesh
