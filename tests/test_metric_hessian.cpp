// Hessians (spacing/hessian.hpp) and the L^p-optimal metric (spacing/hessian_metric.hpp): central
// differences and the least-squares patch fit exact on quadratics, errors naming the data; |H|,
// clipping, the complexity of the metric from mesh data, and the metric of a function against the
// Python evaluator (tools/eval/pdmesh_eval/metric.py); a field sampled on a grid.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/errors.hpp"
#include "error_message.hpp"
#include "spacing/hessian.hpp"
#include "spacing/hessian_metric.hpp"
#include "spacing/mesh_metric_field.hpp"
#include "spacing/metric_complexity.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;
using pdmesh_test::error_message;

namespace {

// u = 3 + x - 2y + 1.5 x² - 0.7 xy + 0.25 y²: H = [[3, -0.7], [-0.7, 0.5]].
double quadratic(Vec2 p) { return 3.0 + p.x - 2.0 * p.y + 1.5 * p.x * p.x - 0.7 * p.x * p.y + 0.25 * p.y * p.y; }
constexpr Hessian kQuadraticH{3.0, -0.7, 0.5};

bool same(const Metric& a, const Metric& b, double eps) {
  const double scale = std::fabs(a.m11) + std::fabs(a.m22) + std::fabs(b.m11) + std::fabs(b.m22);
  return std::fabs(a.m11 - b.m11) <= eps * scale && std::fabs(a.m12 - b.m12) <= eps * scale &&
         std::fabs(a.m22 - b.m22) <= eps * scale;
}

// An n x n grid of [0,1]² with interior points moved by up to 0.3 of a cell (deterministic), two
// triangles per cell with alternating diagonals.
struct GridMesh {
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;
};
GridMesh jittered_grid(int n) {
  GridMesh g;
  const double h = 1.0 / (n - 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      Vec2 p{i * h, j * h};
      if (i > 0 && j > 0 && i + 1 < n && j + 1 < n)
        p = p + 0.3 * h * Vec2{std::sin(12.9898 * i + 78.233 * j), std::cos(39.3467 * i + 11.135 * j)};
      g.points.push_back(p);
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      if ((i + j) % 2 == 0) {
        g.triangles.push_back({a, b, c});
        g.triangles.push_back({a, c, d});
      } else {
        g.triangles.push_back({a, b, d});
        g.triangles.push_back({b, c, d});
      }
    }
  return g;
}

// Each component within eps of the expected matrix's size |m11| + |m22|.
void check_metric_near(const Metric& m, double m11, double m12, double m22, double eps) {
  const double margin = eps * (std::fabs(m11) + std::fabs(m22));
  CHECK(m.m11 == Approx(m11).margin(margin).epsilon(0));
  CHECK(m.m12 == Approx(m12).margin(margin).epsilon(0));
  CHECK(m.m22 == Approx(m22).margin(margin).epsilon(0));
}

}  // namespace

TEST_CASE("hessian_by_differences is exact on quadratics and second order on others", "[hessian]") {
  const Hessian h = hessian_by_differences(quadratic, {0.3, -0.8}, 1e-2);
  CHECK(h.xx == Approx(3.0).epsilon(1e-10));
  CHECK(h.xy == Approx(-0.7).epsilon(1e-10));
  CHECK(h.yy == Approx(0.5).epsilon(1e-10));
  // sin x cos y at (0.4, 0.2): H = [[-sin x cos y, -cos x sin y], [., -sin x cos y]], error O(h²).
  const auto f = [](Vec2 p) { return std::sin(p.x) * std::cos(p.y); };
  const Hessian g = hessian_by_differences(f, {0.4, 0.2}, 1e-3);
  CHECK(g.xx == Approx(-std::sin(0.4) * std::cos(0.2)).epsilon(1e-6));
  CHECK(g.xy == Approx(-std::cos(0.4) * std::sin(0.2)).epsilon(1e-6));
  CHECK(g.yy == Approx(-std::sin(0.4) * std::cos(0.2)).epsilon(1e-6));
}

TEST_CASE("recover_hessians is exact for quadratics at every vertex, corners included", "[hessian]") {
  const GridMesh g = jittered_grid(9);
  std::vector<double> u;
  for (Vec2 p : g.points) u.push_back(quadratic(p));
  const std::vector<Hessian> h = recover_hessians(g.points, g.triangles, u, "u");
  REQUIRE(h.size() == g.points.size());
  for (const Hessian& x : h) {
    CHECK(x.xx == Approx(kQuadraticH.xx).margin(1e-9));
    CHECK(x.xy == Approx(kQuadraticH.xy).margin(1e-9));
    CHECK(x.yy == Approx(kQuadraticH.yy).margin(1e-9));
  }
  // A linear u has a zero Hessian; a point in no triangle gets zero too.
  std::vector<Vec2> points = g.points;
  points.push_back({5.0, 5.0});
  std::vector<double> lin;
  for (Vec2 p : points) lin.push_back(2.0 * p.x - p.y);
  for (const Hessian& x : recover_hessians(points, g.triangles, lin, "u")) {
    CHECK(x.xx == Approx(0.0).margin(1e-9));
    CHECK(x.xy == Approx(0.0).margin(1e-9));
    CHECK(x.yy == Approx(0.0).margin(1e-9));
  }
  // Scaled to a tiny patch (sizes 1e-6), still exact relative to H.
  std::vector<Vec2> small;
  std::vector<double> us;
  for (Vec2 p : g.points) {
    small.push_back(1e-6 * p + Vec2{100.0, 200.0});
    us.push_back(1e-12 * quadratic(p));  // u(x) = 1e-12 q(1e6 (x - offset)): H = H_q
  }
  for (const Hessian& x : recover_hessians(small, g.triangles, us, "u")) CHECK(x.xx == Approx(3.0).epsilon(1e-5));
}

TEST_CASE("recover_hessians refuses data it cannot fit, naming it", "[hessian]") {
  const GridMesh g = jittered_grid(4);
  std::vector<double> u(g.points.size(), 1.0);
  u[5] = std::nan("");
  CHECK_THAT(error_message<InputError>([&] { recover_hessians(g.points, g.triangles, u, "'sol.vtu' array 'T'"); }),
             Contains("'sol.vtu' array 'T'") && Contains("point 5") && Contains("nan"));
  // Points on one line determine no quadratic.
  const std::vector<Vec2> line{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}, {6, 0}};
  const std::vector<std::array<int, 3>> flat{{0, 1, 2}, {1, 2, 3}, {2, 3, 4}, {3, 4, 5}, {4, 5, 6}};
  CHECK_THAT(error_message<InputError>([&] { recover_hessians(line, flat, std::vector<double>(7, 0.0), "u"); }),
             Contains("u: no quadratic fits") && Contains("point 0"));
}

TEST_CASE("abs_hessian, clip_metric and the options' checks", "[hessian]") {
  // H = diag(-4, 9) rotated: |H| has eigenvalues 9 and 4; a zero Hessian gets the floor.
  const Metric r = metric_from_eigen(9.0, -4.0, 0.3);
  const Metric a = abs_hessian({r.m11, r.m12, r.m22}, 1e-8);
  const MetricEigen e = eigen(a);
  CHECK(e.lambda1 == Approx(9.0).epsilon(1e-14));
  CHECK(e.lambda2 == Approx(4.0).epsilon(1e-14));
  CHECK(e.angle == Approx(0.3).epsilon(1e-13));
  CHECK(abs_hessian({}, 1e-8).m11 == 1e-8);
  // Sizes 1e-4 and 10 clipped to [1e-3, 1]: eigenvalues 1e6 and 1.
  const MetricEigen c = eigen(clip_metric(metric_from_sizes(10.0, 1e-4, 0.5), 1e-3, 1.0, 1e9));
  CHECK(c.lambda1 == Approx(1e6).epsilon(1e-12));
  CHECK(c.lambda2 == Approx(1.0).epsilon(1e-12));
  // Anisotropy 100 at most: sizes 1e-3 and 1 become 1e-3 and 0.1.
  const MetricEigen d = eigen(clip_metric(metric_from_sizes(1.0, 1e-3, 0.5), 0.0, 10.0, 100.0));
  CHECK(d.lambda1 == Approx(1e6).epsilon(1e-12));
  CHECK(d.lambda2 == Approx(100.0).epsilon(1e-12));
  CHECK(d.angle == Approx(0.5 - M_PI / 2).epsilon(1e-12));

  HessianMetricOptions o;
  o.complexity = -1.0;
  CHECK_THAT(error_message<InputError>([&] { check_hessian_metric_options(o); }), Contains("complexity = -1"));
  o = {};
  o.hmin = 0.5;
  o.hmax = 0.1;
  CHECK_THAT(error_message<InputError>([&] { check_hessian_metric_options(o); }), Contains("hmax = 0.1"));
  o = {};
  o.max_anisotropy = 0.5;
  CHECK_THAT(error_message<InputError>([&] { check_hessian_metric_options(o); }), Contains("max_anisotropy = 0.5"));
  CHECK(error_message<InputError>([] { check_hessian_metric_options({}); }).empty());
}

TEST_CASE("hessian_metrics_on_mesh reaches the target complexity and is exact for a quadratic", "[hessian]") {
  const GridMesh g = jittered_grid(9);
  std::vector<double> u;
  for (Vec2 p : g.points) u.push_back(quadratic(p));
  HessianMetricOptions o;
  o.complexity = 1000.0;
  const std::vector<Metric> m = hessian_metrics_on_mesh(g.points, g.triangles, u, o, "u");
  // Unclipped, sqrt(det M) = D det|H|^(1/3) is the density times D, so its P1 integral is C exactly.
  CHECK(complexity_on_mesh(g.points, g.triangles, m) == Approx(1000.0).epsilon(1e-9));
  // A constant Hessian on the unit square: M = C det|H|^(-1/2) |H| everywhere (sqrt(det M) = C).
  const Metric h = abs_hessian(kQuadraticH, o.floor);
  const Metric expected = (1000.0 / std::sqrt(h.det())) * h;
  for (const Metric& x : m) check_metric_near(x, expected.m11, expected.m12, expected.m22, 1e-8);
  // As a field on that mesh (the route of data on a background mesh), its complexity is C too.
  const MeshMetricField field(g.points, g.triangles, m, "u");
  CHECK(complexity_on_box(field, Box{{0, 0}, {1, 1}}, 8, 2) == Approx(1000.0).epsilon(1e-8));
  // Clipping at hmax = 0.01 (sizes above it shrink): the complexity grows.
  o.hmax = 0.01;
  const std::vector<Metric> clipped = hessian_metrics_on_mesh(g.points, g.triangles, u, o, "u");
  CHECK(complexity_on_mesh(g.points, g.triangles, clipped) > 1.5 * 1000.0);
}

TEST_CASE("HessianMetricField equals metric.py's l2_optimal_metric", "[hessian]") {
  // Values from tools/eval/pdmesh_eval/metric.py with the cubic u = x³ + 2xy² - y³ + x²/2, whose
  // exact Hessian is [[6x + 1, 4y], [4y, 4x - 6y]] (central differences are exact for cubics):
  //   D = l2_optimal_scale(hessian, 1000.0, grid=64)              -> 481.1345692210529
  //   l2_optimal_metric(hessian, D, hmin=1e-3, hmax=0.3)(points)  -> the (m11, m12, m22) below.
  HessianMetricOptions o;
  o.complexity = 1000.0;
  o.hmin = 1e-3;
  o.hmax = 0.3;
  const HessianMetricField cubic("x^3 + 2*x*y^2 - y^3 + 0.5*x^2", Box{{0, 0}, {1, 1}}, o, 1e-3, 64);
  CHECK(cubic.scale() == Approx(481.1345692210529).epsilon(1e-8));
  check_metric_near(cubic.at({0.25, 0.5}), 1066.6031745925443, 55.407957121690515, 941.9352710687407, 1e-8);
  check_metric_near(cubic.at({0.8, 0.1}), 1778.551389377907, 122.65871650882114, 797.281657307338, 1e-8);
  check_metric_near(cubic.at({0.5, 0.5}), 1487.707892340453, 318.7945483586685, 690.721521443782, 1e-8);
  // The tanh layer of issue 37 (metric.py's exact tanh_hessian, C = 4000, grid 64, sizes in
  // [1e-5, 0.3]): D = 875.6499753162163, and the metrics at two points in the layer below;
  // differences of step 1e-5 agree to about (100 h)² = 1e-6.
  HessianMetricOptions t;
  t.complexity = 4000.0;
  t.hmin = 1e-5;
  t.hmax = 0.3;
  const HessianMetricField layer("tanh(100*(y - 0.5 - 0.25*sin(2*pi*x)))", Box{{0, 0}, {1, 1}}, t, 1e-5, 64);
  CHECK(layer.scale() == Approx(875.6499753162163).epsilon(1e-5));
  check_metric_near(layer.at({0.3, 0.7}), 4968.167572740199, 8533.547245601614, 17580.343488783, 1e-5);
  check_metric_near(layer.at({0.2, 0.74}), 95981.40887432986, -105949.94241807301, 309403.3199914193, 1e-5);
  // Where an eigenvalue of H is 0 (x = 0.5, where sin 2πx has no curvature), the differences' rounding
  // (~1e-16 / h² = 1e-6) lies above |H|'s floor 1e-8 and the two differ; away from it they agree.
  // A bad expression is named.
  CHECK_THAT(error_message<InputError>([&] {
               HessianMetricField("tanh(", Box{{0, 0}, {1, 1}}, t, 1e-5, 4);
             }),
             Contains("'tanh('"));
}

TEST_CASE("sample_metric_grid: the field at the vertices of a grid over the box widened by half a cell",
          "[hessian][gradation]") {
  const Box box{{-1.0, 2.0}, {3.0, 4.0}};
  const int n = 8;
  const ConstantMetricField constant(metric_from_sizes(0.1, 0.01, 0.3));
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Metric> metrics;
  sample_metric_grid(constant, box, n, points, triangles, metrics);
  REQUIRE(points.size() == 81);
  REQUIRE(triangles.size() == 128);
  REQUIRE(metrics.size() == 81);
  // Corners at lo - d/2 and hi + d/2 (d = 0.5 in x, 0.25 in y), row by row from lo.
  CHECK(points.front().x == Approx(-1.25));
  CHECK(points.front().y == Approx(1.875));
  CHECK(points.back().x == Approx(3.25));
  CHECK(points.back().y == Approx(4.125));
  CHECK(points[1].x - points[0].x == Approx(4.5 / 8));
  double area = 0.0;
  for (const auto& t : triangles) {
    const double a = 0.5 * cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]);
    CHECK(a > 0.0);  // counter-clockwise
    area += a;
  }
  CHECK(area == Approx(4.5 * 2.25).epsilon(1e-12));
  for (const Metric& m : metrics) CHECK(same(m, constant.at({0, 0}), 0.0));
  // A grid's metric field is a MeshMetricField that covers the box.
  MeshMetricField field(points, triangles, metrics, "grid");
  CHECK(same(field.at(box.hi), constant.at({0, 0}), 1e-12));
  CHECK_THROWS_AS(sample_metric_grid(constant, box, 0, points, triangles, metrics), InputError);
}
