// Delaunay in a metric (mesh/metric_delaunay.hpp): in a constant metric the result is the isotropic
// Delaunay triangulation of the mapped points; a unit mesh of a stretched metric comes out with Q
// near 1; constraints are kept; no triangle is ever inverted, also in a strongly varying metric;
// cocircular points in the metric flip nothing; the flip bound stops the pass; bad metrics are refused.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>

#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "mesh/constrain.hpp"
#include "mesh/delaunay.hpp"
#include "mesh/metric_delaunay.hpp"
#include "mesh/metric_quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "seeded_random.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"

using namespace pdmesh;
using pdmesh_test::unit;

namespace {

constexpr double kPi = 3.14159265358979323846;

// L with LᵀL = m (upper triangular, Cholesky): |L v| = |v|_m.
Vec2 map_point(const Metric& m, Vec2 p) {
  const double l11 = std::sqrt(m.m11), l12 = m.m12 / l11, l22 = std::sqrt(m.det() / m.m11);
  return {l11 * p.x + l12 * p.y, l22 * p.y};
}

// Each triangle as its sorted vertex triple.
std::set<std::array<int, 3>> triangle_set(const std::vector<std::array<int, 3>>& triangles) {
  std::set<std::array<int, 3>> s;
  for (auto t : triangles) {
    std::sort(t.begin(), t.end());
    s.insert(t);
  }
  return s;
}

// The closed square [lo, hi]² as one curve with `per_side` nodes per side, counter-clockwise (or
// clockwise with `reverse`).
void add_square(NodeSet& nodes, double lo, double hi, int per_side, int curve, bool reverse) {
  std::vector<int> loop;
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < per_side; ++k) {
      const double s = lo + (hi - lo) * k / per_side;
      const Vec2 p = side == 0   ? Vec2{s, lo}
                     : side == 1 ? Vec2{hi, s}
                     : side == 2 ? Vec2{hi + lo - s, hi}
                                 : Vec2{lo, hi + lo - s};
      loop.push_back(nodes.add(p, 0.1, NodeKind::Boundary, curve));
    }
  if (reverse) std::reverse(loop.begin(), loop.end());
  loop.push_back(loop.front());
  nodes.curve_nodes.push_back(loop);
}

// A triangulation's validity without the (isotropic) Delaunay check of check_mesh: every triangle
// counter-clockwise by the exact orient2d, every edge in at most two triangles and then in opposite
// directions, the area, and every boundary edge an edge of the mesh. Returns the problems found.
std::vector<std::string> validity_problems(const Mesh& mesh, double area) {
  std::vector<std::string> problems;
  std::map<std::pair<int, int>, int> directed;
  double sum = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec2 a = mesh.points[t[0]], b = mesh.points[t[1]], c = mesh.points[t[2]];
    if (!(orient2d(a, b, c) > 0.0))
      problems.push_back("triangle " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) +
                         " is not counter-clockwise");
    sum += 0.5 * cross(b - a, c - a);
    for (int i = 0; i < 3; ++i) ++directed[{t[i], t[(i + 1) % 3]}];
  }
  for (const auto& [e, count] : directed)
    if (count != 1)
      problems.push_back("directed edge " + std::to_string(e.first) + "-" + std::to_string(e.second) + " used " +
                         std::to_string(count) + " times");
  if (std::fabs(sum - area) > 1e-9 * area)
    problems.push_back("area " + std::to_string(sum) + " != " + std::to_string(area));
  for (const auto& e : mesh.boundary_edges)
    if (!directed.count({e.a, e.b}) && !directed.count({e.b, e.a}))
      problems.push_back("boundary edge " + std::to_string(e.a) + "-" + std::to_string(e.b) + " missing");
  return problems;
}

double triangles_area(const Mesh& mesh) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles)
    sum += 0.5 * cross(mesh.points[t[1]] - mesh.points[t[0]], mesh.points[t[2]] - mesh.points[t[0]]);
  return sum;
}

Metric linear_metric(Vec2 p) { return metric_from_sizes(0.1, 0.001 + 0.198 * std::fabs(p.y - 0.5), 0.0); }
Metric polar1_metric(Vec2 p) {
  return metric_from_sizes(0.001 + 0.198 * std::fabs(std::hypot(p.x, p.y) - 0.5), 0.1, std::atan2(p.y, p.x));
}

std::vector<Metric> metrics_at(const std::vector<Vec2>& points, Metric (*field)(Vec2)) {
  std::vector<Metric> m;
  for (Vec2 p : points) m.push_back(field(p));
  return m;
}

// A unit mesh of the linear metric on [0, 1] x [ylo, yhi]: rows one metric height (√3/2) apart,
// h_y growing geometrically away from y = 0.5 as the metric's does, 0.1 = h_x apart in each row, odd
// rows shifted by half a step, so that every triangle is nearly equilateral in the metric.
NodeSet linear_unit_mesh() {
  NodeSet nodes;
  const double growth = std::exp(0.198 * std::sqrt(3.0) / 2.0);  // h at the next row, over h here
  std::vector<double> rows{0.5};
  for (double h = 0.001; rows.back() + (growth - 1.0) * h / 0.198 < 1.0;) {
    rows.push_back(rows.back() + (growth - 1.0) * h / 0.198);
    h *= growth;
  }
  const std::size_t up = rows.size();
  for (std::size_t k = 1; k < up; ++k) rows.push_back(1.0 - rows[k]);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::size_t row_index = r < up ? r : r - up + 1;
    const bool odd = row_index % 2 == 1;
    for (int i = 0; i <= 10; ++i) {
      const double x = 0.1 * i + (odd ? 0.05 : 0.0);
      if (x <= 1.0) nodes.add({x, rows[r]}, 0.1, NodeKind::Interior, -1);
    }
  }
  return nodes;
}

}  // namespace

TEST_CASE("metric_incircle is the in-circle test of the mapped points, 0 on a circle of the metric",
          "[metric_delaunay]") {
  std::mt19937_64 rng(5);
  const Metric m = metric_from_sizes(1.0, 0.02, 0.4);
  int agree = 0;
  for (int k = 0; k < 2000; ++k) {
    Vec2 a{unit(rng), unit(rng)}, b{unit(rng), unit(rng)}, c{unit(rng), unit(rng)}, d{unit(rng), unit(rng)};
    if (orient2d(a, b, c) < 0.0) std::swap(b, c);
    const double exact = incircle(map_point(m, a), map_point(m, b), map_point(m, c), map_point(m, d));
    const int s = metric_incircle(a, b, c, d, m);
    REQUIRE(s != 0);  // random points are far from the tie band
    CHECK(s == (exact > 0.0 ? 1 : -1));
    agree += s == (exact > 0.0 ? 1 : -1);
  }
  CHECK(agree == 2000);
  // Points on the ellipse centre + L⁻¹(cos θ, sin θ), a circle of radius 1 in m: cocircular in m.
  const MetricEigen e = eigen(m);
  auto on_ellipse = [&](double theta) {
    const Vec2 v = std::cos(theta) / std::sqrt(e.lambda1) * e.v1() + std::sin(theta) / std::sqrt(e.lambda2) * e.v2();
    return Vec2{0.3, 0.7} + v;
  };
  for (int k = 0; k < 50; ++k) {
    const double t0 = 0.1 * k;
    CHECK(metric_incircle(on_ellipse(t0), on_ellipse(t0 + 1.0), on_ellipse(t0 + 2.5), on_ellipse(t0 + 4.0), m) == 0);
  }
  // Inside and outside that ellipse.
  CHECK(metric_incircle(on_ellipse(0.0), on_ellipse(2.0), on_ellipse(4.0), {0.3, 0.7}, m) == 1);
  const Vec2 far = Vec2{0.3, 0.7} + 1.01 * (on_ellipse(1.0) - Vec2{0.3, 0.7});
  CHECK(metric_incircle(on_ellipse(0.0), on_ellipse(2.0), on_ellipse(4.0), far, m) == -1);
}

TEST_CASE("the quadrilateral's mean metric never asks to undo a flip, the edge-midpoint metric does",
          "[metric_delaunay]") {
  // Random convex quadrilaterals p, a, q, b across the layer of polar-1 (r near 0.5, where h_r
  // changes 100-fold within 0.5): with the metric at the tested edge's midpoint, the edge a-b and
  // the other diagonal p-q are judged in different metrics, and both can ask for a flip: the flip
  // loop would turn such a quadrilateral forever. With the mean over the four vertices, never.
  std::mt19937_64 rng(29);
  auto mean_metric = [](Vec2 p, Vec2 a, Vec2 b, Vec2 q) {
    return exp_metric(0.25 * (log_metric(polar1_metric(p)) + log_metric(polar1_metric(a)) +
                              log_metric(polar1_metric(b)) + log_metric(polar1_metric(q))));
  };
  int midpoint_both = 0, mean_both = 0, tested = 0;
  for (int k = 0; k < 20000; ++k) {
    const double r0 = 0.45 + 0.1 * unit(rng), t0 = 0.2 + unit(rng);
    auto jitter = [&](double dr, double dt) {
      const double r = r0 + dr * (0.3 + unit(rng)), t = t0 + dt * (0.3 + unit(rng));
      return Vec2{r * std::cos(t), r * std::sin(t)};
    };
    const double w = 0.05 * unit(rng);
    const Vec2 p = jitter(-w, 0.0), q = jitter(w, 0.0), a = jitter(0.0, -0.1), b = jitter(0.0, 0.1);
    // t = (p, a, b) and u = (q, b, a) counter-clockwise, p-a-q-b strictly convex.
    if (!(orient2d(p, a, b) > 0.0 && orient2d(q, b, a) > 0.0 && orient2d(p, a, q) > 0.0 && orient2d(q, b, p) > 0.0))
      continue;
    ++tested;
    const Metric mid_ab = polar1_metric(0.5 * (a + b)), mid_pq = polar1_metric(0.5 * (p + q));
    midpoint_both += metric_incircle(p, a, b, q, mid_ab) > 0 && metric_incircle(a, q, p, b, mid_pq) > 0;
    const Metric m = mean_metric(p, a, b, q);
    mean_both += metric_incircle(p, a, b, q, m) > 0 && metric_incircle(a, q, p, b, m) > 0;
  }
  INFO("tested " << tested << ", both diagonals flip: midpoint " << midpoint_both << ", mean " << mean_both);
  CHECK(tested > 5000);
  CHECK(midpoint_both > 0);
  CHECK(mean_both == 0);
}

TEST_CASE("in a constant metric the result is the Delaunay triangulation of the mapped points", "[metric_delaunay]") {
  const auto angle = GENERATE(0.0, 0.5, 2.0);
  const Metric m = metric_from_sizes(0.5, 0.01, angle);
  NodeSet nodes;
  add_square(nodes, 0.0, 1.0, 12, 0, false);
  std::mt19937_64 rng(11);
  while (nodes.size() < 700) nodes.add({0.01 + 0.98 * unit(rng), 0.01 + 0.98 * unit(rng)}, 0.1, NodeKind::Interior, -1);
  MetricDelaunayStats stats;
  const Mesh mesh = triangulate_in_metric(nodes, {"square"}, std::vector<Metric>(nodes.size(), m), {}, &stats);
  CHECK(stats.converged);
  CHECK(stats.flips > 0);
  CHECK(validity_problems(mesh, 1.0).empty());

  NodeSet mapped = nodes;
  for (Vec2& p : mapped.x) p = map_point(m, p);
  const Mesh reference = triangulate(mapped, {"square"});
  const auto got = triangle_set(mesh.triangles), want = triangle_set(reference.triangles);
  CHECK(got.size() == want.size());
  CHECK(got == want);
  // And it is not the isotropic triangulation of the points themselves.
  CHECK(triangle_set(triangulate(nodes, {"square"}).triangles) != got);
}

TEST_CASE("with the identity metric the result is today's triangulation, without a flip", "[metric_delaunay]") {
  NodeSet nodes;
  add_square(nodes, 0.0, 1.0, 10, 0, false);
  std::mt19937_64 rng(3);
  while (nodes.size() < 500) nodes.add({0.01 + 0.98 * unit(rng), 0.01 + 0.98 * unit(rng)}, 0.1, NodeKind::Interior, -1);
  MetricDelaunayStats stats;
  const Mesh mesh = triangulate_in_metric(nodes, {"square"}, std::vector<Metric>(nodes.size(), Metric{}), {}, &stats);
  CHECK(stats.flips == 0);
  CHECK(stats.tests > 0);
  CHECK(mesh.triangles == triangulate(nodes, {"square"}).triangles);
}

TEST_CASE("a unit mesh of the linear metric gets triangles with Q near 1", "[metric_delaunay]") {
  const NodeSet nodes = linear_unit_mesh();
  const auto metrics = metrics_at(nodes.x, linear_metric);
  MetricDelaunayStats stats;
  const Mesh mesh = triangulate_in_metric(nodes, {}, metrics, {}, &stats);
  CHECK(stats.converged);
  INFO("points " << nodes.size() << ", flips " << stats.flips);
  CHECK(validity_problems(mesh, triangles_area(triangulate(nodes, {}))).empty());
  const MetricQualitySummary q = metric_quality(mesh, metrics);
  const MetricQualitySummary iso = metric_quality(triangulate(nodes, {}), metrics);
  INFO("metric: Q min " << q.q_min << " mean " << q.q_mean << " window " << q.window_percent << " %; isotropic: Q min "
                        << iso.q_min << " mean " << iso.q_mean << " window " << iso.window_percent << " %");
  // The triangles along the two sides (x = 0, 1) have one side of two rows and Q = 0.5 by
  // construction; every other triangle is one of the lattice's.
  CHECK(q.q_min > 0.45);
  CHECK(q.q_mean > 0.9);
  std::size_t near_one = 0;
  const auto qs = metric_qualities(mesh.points, mesh.triangles, metrics);
  for (double v : qs) near_one += v > 0.9;
  CHECK(near_one > 0.85 * static_cast<double>(qs.size()));
  CHECK(q.window_percent > 90.0);
  // The same from the field as a muParser expression (the case-file form).
  const auto field = ExpressionMetricField::from_sizes("0.1", "0.001 + 0.198*abs(y-0.5)", "0");
  CHECK(triangulate_in_metric(nodes, {}, field).triangles == mesh.triangles);
  // The isotropic triangulation of the same points is far from it.
  CHECK(iso.q_mean < 0.7);
  CHECK(iso.window_percent < 80.0);
}

TEST_CASE("constraints are kept: a square with a square hole in a rotated stretched metric", "[metric_delaunay]") {
  NodeSet nodes;
  add_square(nodes, 0.0, 1.0, 16, 0, false);
  add_square(nodes, 0.4, 0.6, 4, 1, true);
  std::mt19937_64 rng(17);
  while (nodes.size() < 800) {
    const Vec2 p{0.01 + 0.98 * unit(rng), 0.01 + 0.98 * unit(rng)};
    if (std::max(std::fabs(p.x - 0.5), std::fabs(p.y - 0.5)) > 0.11) nodes.add(p, 0.1, NodeKind::Interior, -1);
  }
  std::vector<Metric> metrics;
  for (Vec2 p : nodes.x) metrics.push_back(metric_from_sizes(0.2, 0.002 + 0.05 * p.x, 0.25 * kPi + p.y));
  MetricDelaunayStats stats;
  const Mesh mesh = triangulate_in_metric(nodes, {"outer", "hole"}, metrics, {}, &stats);
  CHECK(stats.converged);
  CHECK(stats.flips > 0);
  const auto problems = validity_problems(mesh, 1.0 - 0.04);
  INFO((problems.empty() ? std::string("ok") : problems.front()));
  CHECK(problems.empty());
  CHECK(mesh.boundary_edges.size() == 64 + 16);
  for (const auto& t : mesh.triangles) {
    const Vec2 c = (1.0 / 3.0) * (mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]]);
    CHECK_FALSE((std::fabs(c.x - 0.5) < 0.1 && std::fabs(c.y - 0.5) < 0.1));
  }
}

TEST_CASE("no inverted triangle on random points in the polar-1 metric", "[metric_delaunay]") {
  const auto seed = GENERATE(1, 2, 3, 4);
  std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
  NodeSet nodes;
  const bool constrained = seed % 2 == 0;
  if (constrained) add_square(nodes, 0.0, 1.0, 20, 0, false);
  while (nodes.size() < 2000)
    nodes.add({0.005 + 0.99 * unit(rng), 0.005 + 0.99 * unit(rng)}, 0.1, NodeKind::Interior, -1);
  const auto metrics = metrics_at(nodes.x, polar1_metric);
  const std::vector<std::string> names = constrained ? std::vector<std::string>{"square"} : std::vector<std::string>{};
  MetricDelaunayStats stats;
  const Mesh mesh = triangulate_in_metric(nodes, names, metrics, {}, &stats);
  INFO("seed " << seed << ": flips " << stats.flips << ", tests " << stats.tests);
  CHECK(stats.converged);
  const double area = constrained ? 1.0 : triangles_area(triangulate(nodes, names));
  const auto problems = validity_problems(mesh, area);
  INFO((problems.empty() ? std::string("ok") : problems.front()));
  CHECK(problems.empty());
  // Converged: no edge left that the metric test would flip.
  Triangulation tri(nodes.x);
  if (constrained) {
    std::vector<ConstrainedEdge> edges;
    for (std::size_t k = 0; k + 1 < nodes.curve_nodes[0].size(); ++k)
      edges.push_back({nodes.curve_nodes[0][k], nodes.curve_nodes[0][k + 1], 0});
    recover_edges(tri, edges);
  }
  make_metric_delaunay(tri, metrics);
  CHECK(metric_delaunay_violations(tri, metrics).empty());
}

TEST_CASE("cocircular points in the metric terminate without a flip", "[metric_delaunay]") {
  SECTION("a grid in an axis-aligned metric: every cell is cocircular in it") {
    NodeSet nodes;
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) nodes.add({0.05 * i, 0.002 * j}, 0.1, NodeKind::Interior, -1);
    MetricDelaunayStats stats;
    const Mesh mesh = triangulate_in_metric(
        nodes, {}, std::vector<Metric>(nodes.size(), metric_from_sizes(0.05, 0.002, 0.0)), {}, &stats);
    CHECK(stats.converged);
    CHECK(stats.flips == 0);
    CHECK(mesh.triangles.size() == 2 * 19 * 19);
  }
  SECTION("points on one ellipse that is a circle of a rotated metric") {
    const Metric m = metric_from_sizes(1.0, 0.01, 0.7);
    const MetricEigen e = eigen(m);
    NodeSet nodes;
    for (int k = 0; k < 64; ++k) {
      const double t = 2.0 * kPi * k / 64;
      nodes.add(std::cos(t) / std::sqrt(e.lambda1) * e.v1() + std::sin(t) / std::sqrt(e.lambda2) * e.v2(), 0.1,
                NodeKind::Interior, -1);
    }
    MetricDelaunayStats stats;
    const Mesh mesh = triangulate_in_metric(nodes, {}, std::vector<Metric>(nodes.size(), m), {}, &stats);
    CHECK(stats.converged);
    CHECK(stats.flips == 0);
    CHECK(validity_problems(mesh, triangles_area(triangulate(nodes, {}))).empty());
    // Flipping again finds nothing to do.
    Triangulation tri(nodes.x);
    make_metric_delaunay(tri, std::vector<Metric>(nodes.size(), m));
    CHECK(metric_delaunay_violations(tri, std::vector<Metric>(nodes.size(), m)).empty());
  }
}

TEST_CASE("the flip bound stops the pass with a valid triangulation", "[metric_delaunay]") {
  const NodeSet nodes = linear_unit_mesh();
  const auto metrics = metrics_at(nodes.x, linear_metric);
  MetricDelaunayOptions options;
  options.max_flips = 25;
  MetricDelaunayStats stats;
  const Mesh mesh = triangulate_in_metric(nodes, {}, metrics, options, &stats);
  CHECK_FALSE(stats.converged);
  CHECK(stats.flips == 25);
  CHECK(stats.max_flips == 25);
  CHECK(validity_problems(mesh, triangles_area(triangulate(nodes, {}))).empty());
  // The default bound lets the same pass converge.
  MetricDelaunayStats full;
  triangulate_in_metric(nodes, {}, metrics, {}, &full);
  CHECK(full.converged);
  CHECK(full.flips > 25);
  CHECK(full.max_flips >= kMetricFlipsPerEdge * 3 * nodes.size() / 2);
}

TEST_CASE("metrics that are not SPD, or not one per point, are refused by name", "[metric_delaunay]") {
  NodeSet nodes;
  for (int k = 0; k < 10; ++k)
    nodes.add({std::cos(0.6 * k) * (1 + 0.1 * k), std::sin(0.6 * k)}, 0.1, NodeKind::Interior, -1);
  std::vector<Metric> metrics(nodes.size(), Metric{});
  metrics[7] = {1.0, 2.0, 1.0};
  try {
    triangulate_in_metric(nodes, {}, metrics);
    FAIL("no error");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CHECK(what.find("point 7") != std::string::npos);
    CHECK(what.find("not positive definite") != std::string::npos);
  }
  metrics[7] = {std::nan(""), 0.0, 1.0};
  CHECK_THROWS_AS(triangulate_in_metric(nodes, {}, metrics), InputError);
  metrics.pop_back();
  CHECK_THROWS_WITH(triangulate_in_metric(nodes, {}, metrics), Catch::Contains("9 metrics for 10 points"));
}
