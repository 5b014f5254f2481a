// The anisotropic mesh measures (mesh/metric_quality.hpp) against the Python evaluator
// tools/eval/pdmesh_eval/metric.py on one small mesh in issue 37's linear and polar-1 metrics, and
// against closed forms (an equilateral triangle in its metric, an inverted one).
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "mesh/mesh.hpp"
#include "mesh/metric_quality.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_gradation.hpp"

using namespace pdmesh;

namespace {

// A 4 x 4 grid near (0.3, 0.68), jittered, two triangles per cell with alternating diagonals, then
// one clockwise triangle (0, 5, 1). The Python that produced the expected values builds the same:
//   pts = [(0.3 + 0.1*i + 0.013*((i*7 + j*3) % 5 - 2)/2, 0.68 + 0.04*j + 0.004*((i*3 + j*5) % 5 - 2)/2)
//          for j in range(4) for i in range(4)]
//   cell (i, j) with a, b, c, d = 4j+i, 4j+i+1, 4(j+1)+i+1, 4(j+1)+i:
//          (a, b, c), (a, c, d) when (i + j) is even, else (a, b, d), (b, c, d); then (0, 5, 1)
//   from pdmesh_eval import metric as M
//   M.metric_report(pts, tris, M.linear_metric, complexity=465.16874)   (and M.polar1_metric)
//   M.edge_lengths(pts, M.edges(tris), m)[0], [7];  M.qualities(pts, tris, m)[0], [-1]
Mesh test_mesh() {
  Mesh mesh;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      mesh.points.push_back({0.3 + 0.1 * i + 0.013 * ((i * 7 + j * 3) % 5 - 2) / 2.0,
                             0.68 + 0.04 * j + 0.004 * ((i * 3 + j * 5) % 5 - 2) / 2.0});
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int a = 4 * j + i, b = a + 1, c = 4 * (j + 1) + i + 1, d = 4 * (j + 1) + i;
      if ((i + j) % 2 == 0) {
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      } else {
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({b, c, d});
      }
    }
  mesh.triangles.push_back({0, 5, 1});
  return mesh;
}

// metric.py's linear_metric and polar1_metric.
std::vector<Metric> linear_metrics(const Mesh& mesh) {
  std::vector<Metric> m;
  for (Vec2 p : mesh.points) m.push_back(metric_from_sizes(0.1, 0.001 + 0.198 * std::fabs(p.y - 0.5), 0.0));
  return m;
}
std::vector<Metric> polar1_metrics(const Mesh& mesh) {
  std::vector<Metric> m;
  for (Vec2 p : mesh.points)
    m.push_back(metric_from_sizes(0.001 + 0.198 * std::fabs(std::hypot(p.x, p.y) - 0.5), 0.1, std::atan2(p.y, p.x)));
  return m;
}

constexpr double kEps = 1e-12;

}  // namespace

TEST_CASE("metric_quality equals metric.py on a small mesh in the linear metric", "[metric_quality]") {
  const Mesh mesh = test_mesh();
  const std::vector<Metric> m = linear_metrics(mesh);
  const MetricQualitySummary s = metric_quality(mesh, m, 465.16874);
  CHECK(s.vertices == 16);
  CHECK(s.triangles == 19);
  CHECK(s.edges == 33);
  CHECK(s.window_percent == Approx(87.87878787878788).epsilon(kEps));  // 29 of 33
  CHECK(s.length_min == Approx(0.7131913817864156).epsilon(kEps));
  CHECK(s.length_max == Approx(1.6713892395915884).epsilon(kEps));
  CHECK(s.q_min == Approx(-0.852252390389858).epsilon(kEps));  // the clockwise triangle
  CHECK(s.q_mean == Approx(0.7123578218969173).epsilon(kEps));
  CHECK(s.q_below_0_3_percent == Approx(5.263157894736842).epsilon(kEps));  // 1 of 19
  CHECK(s.q_histogram == std::array<std::size_t, kMetricQualityBins>{1, 0, 0, 0, 0, 0, 4, 3, 9, 2});
  CHECK(s.ideal_triangles == Approx(1074.2611890303963).epsilon(kEps));
  CHECK(s.n_over_ideal == Approx(0.01768657398593071).epsilon(kEps));

  const auto edges = triangle_edges(mesh.triangles);
  REQUIRE(edges.size() == 33);
  CHECK(edges[0] == std::array<int, 2>{0, 1});
  CHECK(edges[7] == std::array<int, 2>{2, 6});
  const std::vector<double> l = metric_edge_lengths(mesh.points, edges, m);
  CHECK(l[0] == Approx(1.141941112678869).epsilon(kEps));
  CHECK(l[7] == Approx(1.0099527990040011).epsilon(kEps));
  const std::vector<double> q = metric_qualities(mesh.points, mesh.triangles, m);
  CHECK(q[0] == Approx(0.852252390389858).epsilon(kEps));
  CHECK(q.back() == Approx(-0.852252390389858).epsilon(kEps));
}

TEST_CASE("metric_quality equals metric.py on a small mesh in the polar-1 metric", "[metric_quality]") {
  const Mesh mesh = test_mesh();
  const std::vector<Metric> m = polar1_metrics(mesh);
  const MetricQualitySummary s = metric_quality(mesh, m);
  CHECK(s.window_percent == Approx(60.60606060606061).epsilon(kEps));  // 20 of 33
  CHECK(s.length_min == Approx(0.4252301068133601).epsilon(kEps));
  CHECK(s.length_max == Approx(1.6891641874486911).epsilon(kEps));
  CHECK(s.q_min == Approx(-0.5459094226548656).epsilon(kEps));
  CHECK(s.q_mean == Approx(0.5374515421940169).epsilon(kEps));
  CHECK(s.q_below_0_3_percent == Approx(5.263157894736842).epsilon(kEps));
  CHECK(s.q_histogram == std::array<std::size_t, kMetricQualityBins>{1, 0, 0, 0, 4, 6, 4, 3, 1, 0});
  // No complexity given: no element-count figures.
  CHECK(s.complexity == 0.0);
  CHECK(s.ideal_triangles == 0.0);
  const auto edges = triangle_edges(mesh.triangles);
  const std::vector<double> l = metric_edge_lengths(mesh.points, edges, m);
  CHECK(l[0] == Approx(1.4415828890169946).epsilon(kEps));
  CHECK(l[7] == Approx(0.48074558357821984).epsilon(kEps));
  const std::vector<double> q = metric_qualities(mesh.points, mesh.triangles, m);
  CHECK(q[0] == Approx(0.5459094226548656).epsilon(kEps));
}

TEST_CASE("Q is 1 for a triangle equilateral in its metric and changes sign when inverted", "[metric_quality]") {
  // The unit equilateral triangle mapped by M^(-1/2) for M with sizes 0.1 and 0.001 at 25 degrees is
  // equilateral of side 1 in M: Q = 1 and every edge has length 1.
  const double angle = 25.0 * M_PI / 180.0;
  const Metric m = metric_from_sizes(0.1, 0.001, angle);
  const MetricEigen e = eigen(m);
  const Metric inv_sqrt = metric_from_eigen(1.0 / std::sqrt(e.lambda1), 1.0 / std::sqrt(e.lambda2), e.angle);
  auto map = [&](Vec2 p) {
    return Vec2{inv_sqrt.m11 * p.x + inv_sqrt.m12 * p.y, inv_sqrt.m12 * p.x + inv_sqrt.m22 * p.y};
  };
  Mesh mesh;
  mesh.points = {map({0, 0}), map({1, 0}), map({0.5, std::sqrt(3.0) / 2})};
  mesh.triangles = {{0, 1, 2}, {0, 2, 1}};
  const std::vector<Metric> ms(3, m);
  const std::vector<double> q = metric_qualities(mesh.points, mesh.triangles, ms);
  CHECK(q[0] == Approx(1.0).epsilon(1e-12));
  CHECK(q[1] == Approx(-1.0).epsilon(1e-12));
  const MetricQualitySummary s = metric_quality(mesh, ms, 1.0);
  CHECK(s.window_percent == 100.0);
  CHECK(s.length_min == Approx(1.0).epsilon(1e-12));
  CHECK(s.length_max == Approx(1.0).epsilon(1e-12));
  CHECK(s.q_histogram[0] == 1);  // the inverted copy
  CHECK(s.q_histogram[9] == 1);
  // In physical space that triangle is a sliver: Q measured in the identity is far below 1.
  const std::vector<Metric> identity(3, Metric{});
  CHECK(metric_qualities(mesh.points, {{0, 1, 2}}, identity)[0] < 0.1);
}
