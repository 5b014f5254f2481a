// The cleanup in a metric (host/cleanup/metric_cleanup, docs/metric-fields.md): in a constant
// anisotropic metric its splits and collapses bring the edges into the unit-mesh window
// [1/√2, √2]; no triangle is ever inverted in physical space; boundary nodes stay on their own
// curves in curve order and fixed nodes stay put; flips raise the smallest metric quality Q; the
// case's cleanup settings act; the result is deterministic; a boundary node's collapse into its curve
// neighbour keeps the chains and is undone by the journal; a boundary edge is measured along its curve
// too, so that one whose end metrics miss small sizes between them is split.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "cleanup/editable_mesh.hpp"
#include "cleanup/metric_cleanup.hpp"
#include "cleanup/metric_evaluator.hpp"
#include "cleanup/metric_ops.hpp"
#include "core/predicates.hpp"
#include "geometry/curve_projection.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/metric_quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/boundary_arcs.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"
#include "geometry_fixtures.hpp"

using namespace pdmesh;

namespace {

// The unit square as one closed curve with n segments a side (the boundary nodes' places).
Geometry unit_square(int n) {
  const Vec2 c[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<Vec2> pts;
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < n; ++k) pts.push_back(c[side] + (static_cast<double>(k) / n) * (c[(side + 1) % 4] - c[side]));
  pts.push_back(c[0]);
  return build_geometry({fixtures::raw_polyline(pts, "square")});
}

std::vector<std::string> names(const Geometry& g) {
  std::vector<std::string> out;
  for (const Curve& c : g.curves) out.push_back(c.name);
  return out;
}

std::vector<std::pair<double, double>> fixed_positions(const NodeSet& nodes) {
  std::vector<std::pair<double, double>> out;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes.kind[i] == NodeKind::Fixed) out.push_back({nodes.x[i].x, nodes.x[i].y});
  std::sort(out.begin(), out.end());
  return out;
}

// Nodes of the unit square at isotropic spacing q (the boundary nodes at the geometry's points).
NodeSet square_nodes(const GeometryTree& tree, double q) {
  const ExpressionSpacing spacing(std::to_string(q));
  return make_initial_distribution(tree, spacing, {InitMethod::Structured, 1, {}, false}).nodes;
}

struct Cleaned {
  Mesh before;
  MetricCleanupResult result;
  MetricQualitySummary q_before, q_after;
};

// Triangulates `nodes` in `field`, cleans, and checks what holds for every cleanup: every triangle
// strictly counter-clockwise (exact orient2d), the metrics returned are the field's at the points,
// boundary nodes on their own curve in curve order, fixed nodes where they were, the mesh's area
// that of the boundary polygon.
Cleaned clean_and_verify(const Geometry& g, const GeometryTree& tree, const NodeSet& nodes, const MetricField& field,
                         const MetricCleanupOptions& options = {}) {
  Cleaned c;
  const ExpressionSpacing spacing("0.1");
  c.before = triangulate_in_metric(nodes, names(g), field);
  std::vector<Metric> before_metrics;
  for (const Vec2& p : c.before.points) before_metrics.push_back(field.at(p));
  c.q_before = metric_quality(c.before, before_metrics);
  c.result = clean_mesh_in_metric(c.before, nodes, tree, spacing, field, options);
  const Mesh& m = c.result.mesh;
  REQUIRE(c.result.metrics.size() == m.points.size());
  c.q_after = metric_quality(m, c.result.metrics);
  double area = 0.0;
  for (const auto& t : m.triangles) {
    CHECK(orient2d(m.points[t[0]], m.points[t[1]], m.points[t[2]]) > 0.0);
    area += 0.5 * cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
  }
  CHECK(area == Approx(1.0).epsilon(1e-12));
  for (std::size_t i = 0; i < m.points.size(); i += 7) {
    const Metric want = field.at(m.points[i]);
    CHECK(c.result.metrics[i].m11 == want.m11);
    CHECK(c.result.metrics[i].m22 == want.m22);
  }
  const NodeSet& out = c.result.nodes;
  REQUIRE(out.curve_nodes.size() == nodes.curve_nodes.size());
  for (std::size_t k = 0; k < out.curve_nodes.size(); ++k) {
    double last_arc = -1.0;
    for (int a : out.curve_nodes[k]) {
      const CurvePoint cp =
          closest_on_curve_range(g.curves[k], out.x[a], std::max(0.0, last_arc), g.curves[k].length());
      CHECK(cp.distance <= 1e-12);
      CHECK(cp.arc > last_arc);
      last_arc = cp.arc;
    }
  }
  CHECK(fixed_positions(out) == fixed_positions(nodes));
  return c;
}

// Isotropic size h except near `centre`, where the sizes shrink by 1 + depth e^(-|p - c|²/w²).
class NarrowSmall final : public MetricField {
 public:
  NarrowSmall(double h, Vec2 centre, double depth, double width) : h_(h), c_(centre), depth_(depth), w_(width) {}
  Metric at(Vec2 p) const override {
    const double s = (1.0 + depth_ * std::exp(-norm2(p - c_) / (w_ * w_))) / h_;
    return {s * s, 0.0, s * s};
  }

 private:
  double h_;
  Vec2 c_;
  double depth_, w_;
};

// The metric length along the side y = 0 from x = a to x = b, by the midpoint rule on 4000 steps.
double along_bottom(const MetricField& field, double a, double b) {
  const int n = 4000;
  double total = 0.0;
  for (int k = 0; k < n; ++k) total += field.at({a + (k + 0.5) / n * (b - a), 0.0}).length({(b - a) / n, 0.0});
  return std::fabs(total);
}

}  // namespace

TEST_CASE("metric cleanup: a boundary edge is split where the curve between its ends is long in the metric",
          "[metric_cleanup]") {
  // Nodes 0.25 apart in a metric of size 0.25, but sizes 21 times smaller within about 0.04 of
  // (0.375, 0), between two boundary nodes of the side y = 0: that boundary edge is about 1 long by its
  // end metrics and about 6.7 along the curve.
  const Geometry g = unit_square(4);
  const GeometryTree tree(g);
  const NodeSet nodes = square_nodes(tree, 0.25);
  const NarrowSmall field(0.25, {0.375, 0.0}, 20.0, 0.04);
  REQUIRE(edge_length(field.at({0.25, 0}), field.at({0.5, 0}), {0.25, 0}) < 1.01);
  REQUIRE(along_bottom(field, 0.25, 0.5) > 6.0);
  const Cleaned c = clean_and_verify(g, tree, nodes, field);
  CHECK(c.result.stats.counts.boundary_splits >= 4);
  // Every boundary edge of the side y = 0 is at most √2 long along it, and the ones around the narrow
  // place are no shorter than collapse_below would leave.
  std::vector<double> xs;
  for (const Vec2& p : c.result.mesh.points)
    if (p.y == 0.0) xs.push_back(p.x);
  std::sort(xs.begin(), xs.end());
  double longest = 0.0;
  for (std::size_t k = 1; k < xs.size(); ++k) longest = std::max(longest, along_bottom(field, xs[k - 1], xs[k]));
  INFO("nodes on y = 0: " << xs.size() << ", the longest edge along it " << longest);
  CHECK(longest <= cleanup::kMetricLong * (1.0 + 1e-3));
}

TEST_CASE("metric cleanup: collapses bring edges too short in a constant anisotropic metric into the window",
          "[metric_cleanup]") {
  // Nodes 0.05 apart where the metric asks for 0.15 along x and 0.05 along y: the edges along x
  // (and the boundary edges of the sides along x) are about 1/3 long in the metric.
  const Geometry g = unit_square(20);
  const GeometryTree tree(g);
  const NodeSet nodes = square_nodes(tree, 0.05);
  const ConstantMetricField field(metric_from_sizes(0.15, 0.05, 0.0));
  const Cleaned c = clean_and_verify(g, tree, nodes, field);
  INFO("before " << c.q_before.window_percent << " % Q min " << c.q_before.q_min << "; after "
                 << c.q_after.window_percent << " % Q min " << c.q_after.q_min);
  CHECK(c.q_before.window_percent < 70.0);
  CHECK(c.result.stats.counts.collapses > 0);
  CHECK(c.result.stats.counts.boundary_collapses > 0);
  CHECK(c.q_after.window_percent >= 98.0);
  CHECK(c.q_after.q_min >= 0.6);
  CHECK(c.result.nodes.size() < nodes.size());
}

TEST_CASE("metric cleanup: splits bring edges too long in a constant anisotropic metric into the window",
          "[metric_cleanup]") {
  // Nodes 0.2 apart (boundary nodes 0.25) where the metric asks for 0.1 along y = x and 0.05 across.
  const Geometry g = unit_square(4);
  const GeometryTree tree(g);
  const NodeSet nodes = square_nodes(tree, 0.2);
  const ConstantMetricField field(metric_from_sizes(0.1, 0.05, M_PI / 4));
  const Cleaned c = clean_and_verify(g, tree, nodes, field);
  INFO("before " << c.q_before.window_percent << " % Q min " << c.q_before.q_min << "; after "
                 << c.q_after.window_percent << " % Q min " << c.q_after.q_min);
  CHECK(c.q_before.window_percent < 10.0);
  CHECK(c.result.stats.counts.splits > 0);
  CHECK(c.result.stats.counts.boundary_splits > 0);
  CHECK(c.q_after.window_percent >= 98.0);
  CHECK(c.q_after.q_min >= 0.6);
}

TEST_CASE("metric cleanup: the case's settings act and the result is deterministic", "[metric_cleanup]") {
  const Geometry g = unit_square(20);
  const GeometryTree tree(g);
  const NodeSet nodes = square_nodes(tree, 0.05);
  const ConstantMetricField field(metric_from_sizes(0.15, 0.05, 0.3));
  MetricCleanupOptions no_topology;
  no_topology.topology = false;
  const Cleaned flat = clean_and_verify(g, tree, nodes, field, no_topology);
  CHECK(flat.result.stats.counts.splits + flat.result.stats.counts.collapses == 0);
  CHECK(flat.result.nodes.size() == nodes.size());
  CHECK(flat.q_after.q_min >= flat.q_before.q_min);  // flips and moves only raise the worst Q
  MetricCleanupOptions no_boundary;
  no_boundary.split_boundary = false;
  const Geometry coarse = unit_square(4);
  const GeometryTree coarse_tree(coarse);
  const NodeSet coarse_nodes = square_nodes(coarse_tree, 0.2);
  const Cleaned kept = clean_and_verify(coarse, coarse_tree, coarse_nodes, field, no_boundary);
  CHECK(kept.result.stats.counts.boundary_splits == 0);
  CHECK(kept.result.stats.counts.splits > 0);
  const Cleaned a = clean_and_verify(g, tree, nodes, field), b = clean_and_verify(g, tree, nodes, field);
  CHECK(a.result.mesh.points == b.result.mesh.points);
  CHECK(a.result.mesh.triangles == b.result.mesh.triangles);
}

TEST_CASE("metric cleanup: flips raise the smallest metric quality and never invert", "[metric_cleanup]") {
  // A square split along the diagonal that is long in a metric stretched along it: flipping to the
  // other diagonal makes two triangles that are better in the metric.
  Mesh mesh;
  mesh.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.kind.assign(4, NodeKind::Fixed);
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  cleanup::EditableMesh m(mesh, {}, {});
  // Sizes 0.5 across y = x and 2 along it: the diagonal 0-2 is long, 1-3 short in the metric.
  const ConstantMetricField field(metric_from_sizes(0.5, 2.0, M_PI / 4));
  const cleanup::MetricEvaluator evaluator(m, field);
  m.set_score(&evaluator);
  const Geometry none;
  cleanup::MetricOps ops(m, evaluator, none, {});
  const double before = std::min(m.quality(0), m.quality(1));
  REQUIRE(ops.flip_all(4) == 1);
  const double after = std::min(m.quality(0), m.quality(1));
  CHECK(after > before);
  for (int t = 0; t < 2; ++t) CHECK(orient2d(m.p[m.v[t][0]], m.p[m.v[t][1]], m.p[m.v[t][2]]) > 0.0);
  // Now the other way round: no flip raises the minimum any more.
  CHECK(ops.flip_all(4) == 0);

  // On a random point set: the smallest Q over the mesh never drops, no triangle is inverted.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.02, 0.98);
  const Geometry g = unit_square(10);
  const GeometryTree tree(g);
  NodeSet nodes = make_boundary_nodes(g, ExpressionSpacing("0.1"));
  for (int k = 0; k < 150; ++k) nodes.add({u(rng), u(rng)}, 0.1, NodeKind::Interior, -1);
  const ConstantMetricField stretched(metric_from_sizes(0.2, 0.04, 0.5));
  MetricCleanupOptions only_flips;
  only_flips.topology = false;
  only_flips.smoothing_sweeps = 0;
  const Cleaned c = clean_and_verify(g, tree, nodes, stretched, only_flips);
  CHECK(c.result.stats.counts.flips > 0);
  CHECK(c.q_after.q_min >= c.q_before.q_min);
  CHECK(c.result.nodes.size() == nodes.size());
}

TEST_CASE("metric cleanup: the climb lifts a ball's worst triangle even when edges leave the window",
          "[metric_cleanup]") {
  // Node 4 sits just above the long side 0-1 (2.8) of a fixed trapezoid, in the unit metric: its
  // triangle on that side is flat (Q 0.08) and its edges to 0 and 1 are just inside the window
  // (1.404 < sqrt2). Lifting it raises that triangle's Q (0.16 at y = 0.2, 0.36 at y = 0.45) but takes
  // both edges out of the window from y = 0.2 on, which the window guard alone never allows.
  Mesh mesh;
  mesh.points = {{-1.4, 0.0}, {1.4, 0.0}, {0.7, 1.0}, {-0.7, 1.0}, {0.0, 0.1}};
  mesh.kind = {NodeKind::Fixed, NodeKind::Fixed, NodeKind::Fixed, NodeKind::Fixed, NodeKind::Interior};
  mesh.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  const ConstantMetricField unit(Metric{1.0, 0.0, 1.0});
  const Geometry none;
  const auto climbed = [&](double repair_below) {
    cleanup::EditableMesh m(mesh, {}, {});
    const cleanup::MetricEvaluator evaluator(m, unit);
    m.set_score(&evaluator);
    cleanup::MetricOpsOptions options;
    options.repair_below = repair_below;
    cleanup::MetricOps ops(m, evaluator, none, options);
    for (int sweep = 0; sweep < 40 && ops.climb(0.8) > 0; ++sweep) {
    }
    double lowest = 1.0;
    for (int t = 0; t < 4; ++t) {
      CHECK(orient2d(m.p[m.v[t][0]], m.p[m.v[t][1]], m.p[m.v[t][2]]) > 0.0);
      lowest = std::min(lowest, m.quality(t));
    }
    return lowest;
  };
  // With the guard everywhere (no repair) the node stops where its edges reach sqrt2.
  CHECK(climbed(0.0) < 0.17);
  // By default a ball whose worst Q is below 0.35 climbs past the window: clear of keep_floor's 0.3.
  CHECK(cleanup::MetricOpsOptions{}.repair_below == 0.35);
  CHECK(climbed(cleanup::MetricOpsOptions{}.repair_below) >= 0.33);
}

TEST_CASE("a boundary node collapses into its curve neighbour, and the journal undoes it", "[metric_cleanup]") {
  const Geometry g = unit_square(6);
  const GeometryTree tree(g);
  const NodeSet nodes = square_nodes(tree, 0.15);
  const Mesh mesh = triangulate(nodes, names(g));
  cleanup::EditableMesh m(mesh, nodes.curve_nodes, boundary_arcs(g, nodes));
  // A sliding node whose two curve neighbours slide too.
  int a = -1;
  for (int x = 0; x < m.vertex_slots() && a < 0; ++x)
    if (m.kind[x] == NodeKind::Boundary && m.kind[m.prev[x]] == NodeKind::Boundary &&
        m.kind[m.next[x]] == NodeKind::Boundary)
      a = x;
  REQUIRE(a >= 0);
  const int before = m.prev[a], after = m.next[a];
  const auto v0 = m.v, n0 = m.n;
  // Not into a node that is not its curve neighbour; an interior node has no curve to collapse along.
  int interior = -1;
  for (int x = 0; x < m.vertex_slots() && interior < 0; ++x)
    if (m.kind[x] == NodeKind::Interior) interior = x;
  REQUIRE(interior >= 0);
  CHECK_FALSE(m.collapse_boundary(a, interior));
  CHECK_FALSE(m.collapse_boundary(interior, a));
  CHECK(m.v == v0);

  m.begin();
  REQUIRE(m.collapse_boundary(a, after));
  CHECK(m.removed(a));
  CHECK(m.next[before] == after);
  CHECK(m.prev[after] == before);
  CHECK(m.star_valid(after));
  m.rollback();
  CHECK_FALSE(m.removed(a));
  CHECK(m.next[before] == a);
  CHECK(m.prev[after] == a);
  CHECK(m.v == v0);
  CHECK(m.n == n0);

  REQUIRE(m.collapse_boundary(a, before));
  std::vector<std::vector<int>> chains;
  std::vector<int> old_of_new;
  const Mesh out = m.to_mesh(mesh, chains, old_of_new);
  CHECK(out.points.size() == mesh.points.size() - 1);
  CHECK(out.triangles.size() == mesh.triangles.size() - 1);
  CHECK(chains[0].size() == nodes.curve_nodes[0].size() - 1);
  double area = 0.0;
  for (const auto& t : out.triangles) {
    CHECK(orient2d(out.points[t[0]], out.points[t[1]], out.points[t[2]]) > 0.0);
    area += 0.5 * cross(out.points[t[1]] - out.points[t[0]], out.points[t[2]] - out.points[t[0]]);
  }
  // The domain loses the sliver between the removed node and the new boundary edge: none on a
  // straight side.
  CHECK(area == Approx(1.0).epsilon(1e-12));
  // Every boundary edge joins consecutive chain nodes, and is an edge of a triangle.
  for (const auto& e : out.boundary_edges) {
    bool found = false;
    for (const auto& t : out.triangles)
      for (int k = 0; k < 3; ++k)
        found = found || (t[k] == e.a && t[(k + 1) % 3] == e.b) || (t[k] == e.b && t[(k + 1) % 3] == e.a);
    CHECK(found);
  }
}
