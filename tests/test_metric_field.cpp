// Metric fields from muParser expressions (spacing/metric_field.hpp): both forms against
// metric_from_sizes, the errors naming the expression and the value; metrics on a mesh
// (spacing/mesh_metric_field.hpp) against log-Euclidean interpolation; and the complexity
// C = ∫ sqrt(det M) (spacing/metric_complexity.hpp) against closed forms and the Python evaluator.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/errors.hpp"
#include "error_message.hpp"
#include "spacing/hessian_metric.hpp"
#include "spacing/mesh_metric_field.hpp"
#include "spacing/metric_complexity.hpp"
#include "spacing/metric_field.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;
using pdmesh_test::error_message;

namespace {

void check_same(const Metric& a, const Metric& b, double eps) {
  const double scale = std::fabs(a.m11) + std::fabs(a.m22);
  CHECK(std::fabs(a.m11 - b.m11) <= eps * scale);
  CHECK(std::fabs(a.m12 - b.m12) <= eps * scale);
  CHECK(std::fabs(a.m22 - b.m22) <= eps * scale);
}

const Box kUnitSquare{{0.0, 0.0}, {1.0, 1.0}};

}  // namespace

TEST_CASE("ExpressionMetricField in sizes form: issue 37's linear and polar-1 metrics", "[metric_field]") {
  const auto linear = ExpressionMetricField::from_sizes("0.1", "0.001 + 0.198*abs(y-0.5)", "0");
  for (Vec2 p : {Vec2{0.2, 0.5}, Vec2{0.7, 0.9}, Vec2{0.0, 0.1}})
    check_same(linear.at(p), metric_from_sizes(0.1, 0.001 + 0.198 * std::fabs(p.y - 0.5), 0.0), 1e-15);
  // polar-1: h_r along the radius, h_t = 0.1 across; the angle in degrees.
  const auto polar =
      ExpressionMetricField::from_sizes("0.001 + 0.198*abs(sqrt(x^2+y^2)-0.5)", "0.1", "atan2(y, x)*180/pi");
  for (Vec2 p : {Vec2{0.6, 0.1}, Vec2{0.3, 0.8}, Vec2{0.9, 0.9}}) {
    const double r = std::hypot(p.x, p.y);
    const Metric expected = metric_from_sizes(0.001 + 0.198 * std::fabs(r - 0.5), 0.1, std::atan2(p.y, p.x));
    check_same(polar.at(p), expected, 1e-13);
    // The radial step of h_r has unit length.
    CHECK(polar.at(p).length((0.001 + 0.198 * std::fabs(r - 0.5)) / r * p) == Approx(1.0).epsilon(1e-12));
  }
}

TEST_CASE("ExpressionMetricField in components form", "[metric_field]") {
  const auto f = ExpressionMetricField::from_components("100 + x", "10*y", "400");
  const Metric m = f.at({2.0, 3.0});
  CHECK(m.m11 == 102.0);
  CHECK(m.m12 == 30.0);
  CHECK(m.m22 == 400.0);
}

TEST_CASE("ExpressionMetricField refuses bad expressions and values naming them", "[metric_field]") {
  CHECK_THAT(error_message<InputError>([] { ExpressionMetricField::from_sizes("0.1", "0.01*(", "0"); }),
             Contains("h2 = '0.01*('"));
  CHECK_THAT(error_message<InputError>([] { ExpressionMetricField::from_sizes("0.1", "0.1", "z"); }),
             Contains("angle = 'z'"));
  CHECK_THAT(error_message<InputError>([] { ExpressionMetricField::from_components("1", "q", "1"); }),
             Contains("m12 = 'q'"));
  // A size that is negative somewhere: named with the point and the value.
  const auto negative = ExpressionMetricField::from_sizes("0.1", "y - 0.5", "0");
  CHECK_NOTHROW(negative.at({0.0, 0.75}));
  CHECK_THAT(error_message<InputError>([&] {
               negative.at({0.25, 0.25});
             }),
             Contains("h2 = 'y - 0.5'") && Contains("(0.25, 0.25)") && Contains("-0.25") && Contains("positive"));
  const auto nan = ExpressionMetricField::from_sizes("sqrt(x)", "0.1", "0");
  CHECK_THAT(error_message<InputError>([&] { nan.at({-1.0, 0.0}); }), Contains("h1 = 'sqrt(x)'") && Contains("nan"));
  const auto zero = ExpressionMetricField::from_sizes("0.1", "0.1", "1/x");
  CHECK_THAT(error_message<InputError>([&] { zero.at({0.0, 0.0}); }), Contains("angle = '1/x'") && Contains("inf"));
  // Components that are not SPD at a point.
  const auto indefinite = ExpressionMetricField::from_components("1", "x", "1");
  CHECK_NOTHROW(indefinite.at({0.5, 0.0}));
  CHECK_THAT(error_message<InputError>([&] {
               indefinite.at({2.0, 0.0});
             }),
             Contains("m12 = 'x'") && Contains("(2, 0)") && Contains("(1, 2, 1)") && Contains("not positive definite"));
  CHECK_THAT(error_message<InputError>([] {
               ConstantMetricField(Metric{1.0, 0.0, -1.0});
             }),
             Contains("constant metric field") && Contains("(1, 0, -1)"));
}

TEST_CASE("complexity of a constant metric on the unit square is sqrt(det M)", "[metric_field][complexity]") {
  // h1 = 0.1, h2 = 0.02: sqrt(det M) = 1 / (h1 h2) = 500, whatever the angle.
  const ConstantMetricField f(metric_from_sizes(0.1, 0.02, 30.0 * M_PI / 180.0));
  CHECK(complexity_on_box(f, kUnitSquare, 3, 2) == Approx(500.0).epsilon(1e-12));
  CHECK(complexity_on_box(f, Box{{-1.0, 0.0}, {1.0, 0.5}}, 3, 2) == Approx(500.0).epsilon(1e-12));
  CHECK(ideal_triangles(500.0) == Approx(4.0 * 500.0 / std::sqrt(3.0)).epsilon(1e-15));
  // On a mesh of the square (two triangles) the P1 rule is exact for a constant.
  const std::vector<Vec2> points{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<std::array<int, 3>> triangles{{0, 1, 2}, {0, 2, 3}};
  CHECK(complexity_on_mesh(points, triangles, std::vector<Metric>(4, f.at({}))) == Approx(500.0).epsilon(1e-12));
}

TEST_CASE("complexity of the linear case against its closed form and metric.py", "[metric_field][complexity]") {
  const auto linear = ExpressionMetricField::from_sizes("0.1", "0.001 + 0.198*abs(y-0.5)", "0");
  // metric.py: complexity_square(linear_metric, panels=40) = 464.93847528718663 (the same rule:
  // 40 x 40 cells of 4 x 4 Gauss points, cell faces at the kink y = 0.5).
  CHECK(complexity_on_box(linear, kUnitSquare, 40, 4) == Approx(464.93847528718663).epsilon(1e-12));
  // Closed form: ∫ 10 / (0.001 + 0.198 |y - 0.5|) dy = (20 / 0.198) ln 100 = 465.1687056553628;
  // 40 panels reach it to 5e-4, 160 panels to better than 1e-5.
  CHECK(complexity_on_box(linear, kUnitSquare, 40, 4) == Approx(465.1687056553628).epsilon(1e-3));
  CHECK(complexity_on_box(linear, kUnitSquare, 160, 4) == Approx(465.1687056553628).epsilon(1e-5));
}

TEST_CASE("MeshMetricField interpolates log-Euclidean inside and along the nearest boundary edge", "[metric_field]") {
  // The unit square as two counter-clockwise triangles, a different metric at each corner.
  const std::vector<Vec2> points{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<std::array<int, 3>> triangles{{0, 1, 2}, {0, 2, 3}};
  const std::vector<Metric> m{metric_from_sizes(0.1, 0.001, 0.0), metric_from_sizes(0.05, 0.02, 0.7),
                              metric_from_sizes(0.3, 0.3, 0.0), metric_from_sizes(0.01, 0.2, -1.2)};
  const MeshMetricField f(points, triangles, m, "'m.vtu'");
  for (int i = 0; i < 4; ++i) {
    const Metric at = f.at(points[i]);
    CHECK(at.m11 == m[i].m11);  // a corner's own metric, exactly
    CHECK(at.m12 == m[i].m12);
    CHECK(at.m22 == m[i].m22);
  }
  check_same(f.at({0.5, 0.0}), interpolate(m[0], m[1], 0.5), 1e-13);
  check_same(f.at({0.25, 0.25}), interpolate(m[0], m[2], 0.25), 1e-13);  // on the shared diagonal
  check_same(f.at({2.0 / 3.0, 1.0 / 3.0}), log_euclidean_mean({m[0], m[1], m[2]}, {1, 1, 1}), 1e-13);
  // Outside: the nearest boundary point's interpolation; beyond a corner, the corner's metric.
  check_same(f.at({0.5, -3.0}), interpolate(m[0], m[1], 0.5), 1e-13);
  check_same(f.at({1.5, 0.75}), interpolate(m[1], m[2], 0.75), 1e-13);
  check_same(f.at({-1.0, -1.0}), m[0], 0.0);
  // Equal metrics stay equal everywhere.
  const MeshMetricField same_everywhere(points, triangles, std::vector<Metric>(4, m[1]), "x");
  for (Vec2 p : {Vec2{0.3, 0.1}, Vec2{0.1, 0.9}, Vec2{0.5, 0.5}, Vec2{3.0, 3.0}})
    check_same(same_everywhere.at(p), m[1], 1e-13);
}

TEST_CASE("MeshMetricField::at_many gives at()'s metrics bit for bit, whatever its guesses", "[metric_field]") {
  // A 40 x 40 grid of a turning, stretching metric; points inside cells, on edges, at corners and
  // outside, moved a little between calls so that the guesses of the last call are right, wrong
  // (another cell), out of range, or stale after the points were reordered.
  const ExpressionMetricField field =
      ExpressionMetricField::from_sizes("0.1", "0.001 + 0.2*abs(y - 0.5 - 0.2*sin(6*x))", "30*x + 40*y");
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Metric> metrics;
  sample_metric_grid(field, kUnitSquare, 40, points, triangles, metrics);
  const MeshMetricField f(points, triangles, metrics, "grid");
  std::vector<Vec2> p;
  for (int k = 0; k < 3000; ++k) {
    const double u = std::fmod(0.6180339887 * k, 1.0), v = std::fmod(0.7548776662 * k, 1.0);
    p.push_back({1.2 * u - 0.1, 1.2 * v - 0.1});
  }
  for (std::size_t k = 0; k < 40; ++k) p.push_back(points[k * 37 % points.size()]);  // grid points
  for (std::size_t k = 0; k + 1 < 40; ++k)                                           // midpoints of grid edges
    p.push_back({0.5 * (points[k].x + points[k + 1].x), 0.5 * (points[k].y + points[k + 1].y)});
  std::vector<int> guesses;
  std::vector<Metric> out;
  for (int call = 0; call < 4; ++call) {
    INFO("call " << call);
    if (call == 2) guesses.assign(p.size(), static_cast<int>(triangles.size()) + 5);
    if (call == 3) std::reverse(p.begin(), p.end());
    f.at_many(p, out, guesses);
    REQUIRE(out.size() == p.size());
    REQUIRE(guesses.size() == p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Metric m = f.at(p[i]);
      INFO("point " << i << " (" << p[i].x << ", " << p[i].y << ")");
      REQUIRE(out[i].m11 == m.m11);
      REQUIRE(out[i].m12 == m.m12);
      REQUIRE(out[i].m22 == m.m22);
    }
    for (Vec2& q : p) q = {q.x + 0.004, q.y - 0.003};
  }
  // The base class's at_many is at() in order, for any field.
  const ConstantMetricField constant(metric_from_sizes(0.1, 0.01, 0.3));
  std::vector<Metric> plain;
  constant.at_many(p, plain, guesses);
  REQUIRE(plain.size() == p.size());
  for (std::size_t i = 0; i < p.size(); i += 97) CHECK(plain[i].m12 == constant.at(p[i]).m12);
}

TEST_CASE("MeshMetricField refuses bad data naming it", "[metric_field]") {
  const std::vector<Vec2> points{{0, 0}, {1, 0}, {1, 1}};
  const std::vector<Metric> good(3, Metric{});
  std::vector<Metric> bad = good;
  bad[2] = Metric{1.0, 0.0, -4.0};
  CHECK_THAT(error_message<InputError>([&] {
               MeshMetricField(points, {{0, 1, 2}}, bad, "'m.vtu' array 'M'");
             }),
             Contains("'m.vtu' array 'M': point 2 (1, 1)") && Contains("(1, 0, -4)"));
  CHECK_THAT(error_message<InputError>([&] {
               MeshMetricField(points, {{0, 2, 1}}, good, "'m.vtu'");
             }),
             Contains("triangle 0 (0, 2, 1)") && Contains("positive area"));
  CHECK_THAT(error_message<InputError>([&] {
               MeshMetricField(points, {{0, 1, 3}}, good, "'m.vtu'");
             }),
             Contains("uses point 3"));
  CHECK_THAT(error_message<InputError>([&] { MeshMetricField(points, {}, good, "'m.vtu'"); }),
             Contains("at least one triangle"));
  CHECK_THAT(error_message<InputError>([&] {
               MeshMetricField(points, {{0, 1, 2}}, {Metric{}}, "'m.vtu'");
             }),
             Contains("1 metrics for 3 points"));
  // The same triangle twice leaves the mesh without a boundary edge (at() outside it found none:
  // found by fuzzing the Medit reader); a triangle folded over another; an edge of three triangles.
  CHECK_THAT(error_message<InputError>([&] {
               MeshMetricField(points, {{0, 1, 2}, {1, 2, 0}}, good, "'m.mesh'");
             }),
             Contains("'m.mesh': the triangles 0 (0, 1, 2) and 1 (1, 2, 0) lie on the same side of their shared edge"));
  const std::vector<Vec2> five{{0, 0}, {1, 0}, {1, 1}, {0.5, 2}, {0.5, -1}};
  CHECK_THAT(error_message<InputError>([&] {
               MeshMetricField(five, {{0, 1, 2}, {0, 1, 3}}, std::vector<Metric>(5, Metric{}), "'m.vtu'");
             }),
             Contains("lie on the same side of their shared edge point 0 (0, 0) - point 1 (1, 0)"));
  CHECK_THAT(error_message<InputError>([&] {
               MeshMetricField(five, {{0, 1, 2}, {1, 0, 4}, {0, 1, 3}}, std::vector<Metric>(5, Metric{}), "'m.vtu'");
             }),
             Contains("'m.vtu':") && Contains("triangles"));
}
