// The 2x2 metric algebra (spacing/metric.hpp) against closed forms: sizes and rotations, the
// eigen-decomposition, validation messages, edge lengths, log-Euclidean interpolation, intersection;
// and metric gradation on a graph of points (spacing/metric_gradation.hpp).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "core/errors.hpp"
#include "error_message.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_gradation.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;
using pdmesh_test::error_message;

namespace {

constexpr double kDeg = M_PI / 180.0;

Vec2 direction(double angle) { return {std::cos(angle), std::sin(angle)}; }

// The same matrix up to `eps` relative to its size.
bool same(const Metric& a, const Metric& b, double eps) {
  const double scale = std::fabs(a.m11) + std::fabs(a.m22) + std::fabs(b.m11) + std::fabs(b.m22);
  return std::fabs(a.m11 - b.m11) <= eps * scale && std::fabs(a.m12 - b.m12) <= eps * scale &&
         std::fabs(a.m22 - b.m22) <= eps * scale;
}

// A few SPD metrics of different shapes, sizes and directions.
std::vector<Metric> sample_metrics() {
  return {metric_from_sizes(0.1, 0.001, 0.0),       metric_from_sizes(0.1, 0.02, 30 * kDeg),
          metric_from_sizes(2.0, 0.5, -70 * kDeg),  metric_from_sizes(1e-3, 1e-3, 0.0),
          metric_from_sizes(0.05, 0.3, 100 * kDeg), Metric{3.0, 1.0, 2.0}};
}

}  // namespace

TEST_CASE("metric_from_sizes: h1 along the angle, h2 across, eigenvalues 1/h²", "[metric]") {
  const Metric m = metric_from_sizes(0.1, 0.02, 30 * kDeg);
  // Along 30 degrees a step of h1 has length 1, across it a step of h2.
  CHECK(m.length(0.1 * direction(30 * kDeg)) == Approx(1.0).epsilon(1e-14));
  CHECK(m.length(0.02 * direction(120 * kDeg)) == Approx(1.0).epsilon(1e-14));
  CHECK(m.det() == Approx(1.0 / (0.1 * 0.1 * 0.02 * 0.02)).epsilon(1e-13));
  const MetricEigen e = eigen(m);
  CHECK(e.lambda1 == Approx(2500.0).epsilon(1e-13));  // 1/h2², the larger
  CHECK(e.lambda2 == Approx(100.0).epsilon(1e-13));   // 1/h1²
  // lambda1's eigenvector is across the 30-degree direction: 120 degrees, i.e. -60 in (-90, 90].
  CHECK(e.angle == Approx(-60 * kDeg).epsilon(1e-13));
  CHECK(std::fabs(dot(e.v1(), direction(30 * kDeg))) < 1e-14);
  CHECK(cross(e.v1(), e.v2()) == Approx(1.0));
  // The unrotated metric is diagonal.
  const Metric d = metric_from_sizes(0.1, 0.02, 0.0);
  CHECK(d.m11 == Approx(100.0).epsilon(1e-15));
  CHECK(d.m12 == 0.0);
  CHECK(d.m22 == Approx(2500.0).epsilon(1e-15));
}

TEST_CASE("eigen and metric_from_eigen are inverse, also for very anisotropic metrics", "[metric]") {
  for (const Metric& m : sample_metrics()) {
    const MetricEigen e = eigen(m);
    CHECK(e.lambda1 >= e.lambda2);
    CHECK(e.lambda2 > 0.0);
    CHECK(same(metric_from_eigen(e.lambda1, e.lambda2, e.angle), m, 1e-14));
    CHECK(e.lambda1 * e.lambda2 == Approx(m.det()).epsilon(1e-12));
  }
  // Sizes 0.1 and 1e-4 (eigenvalues 1e8 apart): the small eigenvalue keeps its relative accuracy.
  const MetricEigen e = eigen(metric_from_sizes(0.1, 1e-4, 0.3));
  CHECK(e.lambda2 == Approx(100.0).epsilon(1e-10));
  CHECK(e.lambda1 == Approx(1e8).epsilon(1e-12));
}

TEST_CASE("check_metric and check_sizes refuse bad metrics naming the object and the value", "[metric]") {
  CHECK(is_spd(Metric{1.0, 0.5, 1.0}));
  CHECK_FALSE(is_spd(Metric{1.0, 1.0, 1.0}));  // singular
  CHECK_FALSE(is_spd(Metric{1.0, 2.0, 1.0}));  // indefinite
  CHECK_FALSE(is_spd(Metric{-1.0, 0.0, -1.0}));
  CHECK_FALSE(is_spd(Metric{std::nan(""), 0.0, 1.0}));
  // m11 m22 - m12² overflows here; the test must still see that |m12| > sqrt(m11 m22).
  CHECK_FALSE(is_spd(Metric{1e200, 1.1e200, 1e200}));
  CHECK(is_spd(Metric{1e200, 0.9e200, 1e200}));

  const std::string indefinite = error_message<InputError>([] { check_metric({1.0, 2.0, 1.0}, "point 7 of 'm.vtu'"); });
  CHECK_THAT(indefinite, Contains("point 7 of 'm.vtu'") && Contains("(1, 2, 1)") && Contains("not positive definite") &&
                             Contains("-3"));
  const std::string nan = error_message<InputError>([] { check_metric({1.0, std::nan(""), 1.0}, "metric at (0, 0)"); });
  CHECK_THAT(nan, Contains("metric at (0, 0)") && Contains("nan") && Contains("not finite"));
  CHECK(error_message<InputError>([] { check_metric({1.0, 0.0, 2.0}, "ok"); }).empty());

  CHECK_THAT(error_message<InputError>([] { check_sizes(0.1, -0.5, 0.0, "sizes at (1, 2)"); }),
             Contains("sizes at (1, 2)") && Contains("h2 = -0.5"));
  CHECK_THAT(error_message<InputError>([] { check_sizes(0.0, 1.0, 0.0, "s"); }), Contains("h1 = 0"));
  CHECK_THAT(error_message<InputError>([] { check_sizes(1.0, 1.0, std::numeric_limits<double>::infinity(), "s"); }),
             Contains("angle = inf"));
  CHECK(error_message<InputError>([] { check_sizes(0.1, 0.2, 1.0, "s"); }).empty());
}

TEST_CASE("edge_length: |v|_M for equal ends, the log formula between, and its quadrature check", "[metric]") {
  const Metric m = metric_from_sizes(0.1, 0.02, 30 * kDeg);
  const Vec2 v{0.03, 0.05};
  CHECK(edge_length(m, m, v) == Approx(m.length(v)).epsilon(1e-15));
  // mb = 4 ma: Lb = 2 La, L = (La - 2 La) / ln(1/2) = La / ln 2.
  const Metric m4 = 4.0 * m;
  const double la = m.length(v);
  CHECK(edge_length(m, m4, v) == Approx(la / std::log(2.0)).epsilon(1e-14));
  CHECK(edge_length(m4, m, v) == Approx(la / std::log(2.0)).epsilon(1e-14));
  // The interpolated metric along the edge is 4^t ma, so the quadrature of |v|_M(t) agrees.
  CHECK(edge_length_quadrature(m, m4, v) == Approx(la / std::log(2.0)).epsilon(1e-12));
  // Within 1e-3 of each other the mean is taken (the log formula loses digits there).
  const Metric near = (1.0 + 1e-4) * m;
  CHECK(edge_length(m, near, v) == 0.5 * (m.length(v) + near.length(v)));
  // For metrics of different shapes the log formula stays between the two end lengths. (The
  // log-Euclidean path need not: between these two, |w| dips below both ends, so the two lengths
  // differ there.)
  const Metric a = metric_from_sizes(0.1, 0.01, 0.0), b = metric_from_sizes(0.05, 0.05, 0.0);
  const Vec2 w{0.04, 0.01};
  const double l = edge_length(a, b, w);
  CHECK(l > std::min(a.length(w), b.length(w)));
  CHECK(l < std::max(a.length(w), b.length(w)));
  CHECK(edge_length_quadrature(a, b, w) < std::min(a.length(w), b.length(w)));
}

TEST_CASE("log-Euclidean interpolation keeps equal metrics and interpolates det geometrically", "[metric]") {
  for (const Metric& m : sample_metrics()) {
    CHECK(same(exp_metric(log_metric(m)), m, 1e-13));
    for (double t : {0.0, 0.25, 0.5, 0.9, 1.0}) CHECK(same(interpolate(m, m, t), m, 1e-13));
    CHECK(same(log_euclidean_mean({m, m, m}, {0.2, 0.3, 0.5}), m, 1e-13));
  }
  const Metric a = metric_from_sizes(0.1, 0.001, 0.0), b = metric_from_sizes(0.05, 0.3, 100 * kDeg);
  CHECK(same(interpolate(a, b, 0.0), a, 1e-13));
  CHECK(same(interpolate(a, b, 1.0), b, 1e-13));
  for (double t : {0.1, 0.5, 0.7}) {
    const Metric m = interpolate(a, b, t);
    CHECK(is_spd(m));
    // det(exp X) = exp(tr X): det M(t) = det(a)^(1-t) det(b)^t.
    CHECK(m.det() == Approx(std::pow(a.det(), 1.0 - t) * std::pow(b.det(), t)).epsilon(1e-11));
  }
  // The mean with weights (1, 1) is the midpoint of the interpolation; weights need not sum to 1.
  CHECK(same(log_euclidean_mean({a, b}, {1.0, 1.0}), interpolate(a, b, 0.5), 1e-13));
  CHECK(same(log_euclidean_mean({a, b}, {3.0, 1.0}), interpolate(a, b, 0.25), 1e-13));
}

TEST_CASE("intersect contains both metrics and keeps the larger along their common axes", "[metric]") {
  // Axis-aligned: the larger of each diagonal entry.
  const Metric i0 = intersect(Metric{1.0, 0.0, 100.0}, Metric{100.0, 0.0, 1.0});
  CHECK(same(i0, Metric{100.0, 0.0, 100.0}, 1e-14));
  const std::vector<Metric> ms = sample_metrics();
  for (const Metric& a : ms)
    for (const Metric& b : ms) {
      const Metric c = intersect(a, b);
      CHECK(is_spd(c));
      for (int k = 0; k < 72; ++k) {
        const Vec2 v = direction(k * 2.5 * kDeg);
        // Up to rounding relative to the matrix (whose eigenvalues may be 1e4 apart).
        CHECK(c.quad(v) >= std::max(a.quad(v), b.quad(v)) - 1e-13 * (c.m11 + c.m22));
      }
      // Symmetric up to rounding, and idempotent.
      CHECK(same(c, intersect(b, a), 1e-12));
      CHECK(same(intersect(c, a), c, 1e-12));
    }
  // A metric that contains the other is the intersection.
  const Metric a = metric_from_sizes(0.1, 0.02, 30 * kDeg);
  const Metric b = a + metric_from_sizes(0.05, 1.0, 80 * kDeg);  // a plus a PSD part
  CHECK(same(intersect(a, b), b, 1e-13));
  CHECK(same(intersect(b, a), b, 1e-13));
  // Not more than needed: along a common eigenvector the result equals one of the two.
  const Metric x = metric_from_sizes(0.1, 0.01, 0.0), y = metric_from_sizes(0.02, 0.05, 0.0);
  const Metric xy = intersect(x, y);
  CHECK(xy.m11 == Approx(1.0 / (0.02 * 0.02)).epsilon(1e-13));
  CHECK(xy.m22 == Approx(1.0 / (0.01 * 0.01)).epsilon(1e-13));
}

TEST_CASE("span_metric grows a metric by the gradation beta along an edge", "[metric][gradation]") {
  const double beta = 1.5;
  const Metric m = metric_from_sizes(0.1, 0.01, 20 * kDeg);
  const Vec2 v{0.05, 0.02};
  // Metric space (t = 0): m / eta² with eta = 1 + |v|_m ln beta, the shape kept.
  const double eta = 1.0 + m.length(v) * std::log(beta);
  CHECK(same(span_metric(m, v, beta, 0.0), (1.0 / (eta * eta)) * m, 1e-14));
  // Physical space (t = 1): each size h_i grows by |v| ln beta.
  const Metric p = span_metric(m, v, beta, 1.0);
  const MetricEigen e = eigen(p);
  CHECK(1.0 / std::sqrt(e.lambda1) == Approx(0.01 + norm(v) * std::log(beta)).epsilon(1e-13));
  CHECK(1.0 / std::sqrt(e.lambda2) == Approx(0.1 + norm(v) * std::log(beta)).epsilon(1e-13));
  // For an isotropic metric every t gives the same.
  const Metric iso = metric_from_sizes(0.1, 0.1, 0.0);
  CHECK(same(span_metric(iso, v, beta, 0.0), span_metric(iso, v, beta, 1.0), 1e-14));
  CHECK(same(span_metric(iso, v, beta, 0.0), span_metric(iso, v, beta, 0.125), 1e-14));
  // The spanned metric at the far end has gradation beta exactly, from either end.
  CHECK(edge_gradation(m, span_metric(m, v, beta, 0.0), v) == Approx(beta).epsilon(1e-12));
  CHECK(edge_gradation(span_metric(m, v, beta, 0.0), m, v) == Approx(beta).epsilon(1e-12));
  CHECK(edge_gradation(m, m, v) == 1.0);
  CHECK(edge_gradation(m, 100.0 * m, v) > beta);
}

TEST_CASE("limit_metric_gradation: every edge within beta, metrics only grow, the smallest kept",
          "[metric][gradation]") {
  // A 12 x 12 grid of the unit square, isotropic size 0.1, with one point of size 0.001.
  const int n = 12;
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) points.push_back({i / (n - 1.0), j / (n - 1.0)});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      triangles.push_back({a, a + 1, a + n + 1});
      triangles.push_back({a, a + n + 1, a + n});
    }
  const auto edges = triangle_edges(triangles);
  CHECK(edges.size() == static_cast<std::size_t>(3 * (n - 1) * (n - 1) + 2 * (n - 1)));
  for (double t : {0.0, 0.125, 1.0}) {
    std::vector<Metric> m(points.size(), metric_from_sizes(0.1, 0.1, 0.0));
    const int small = 5 * n + 5;
    m[small] = metric_from_sizes(0.001, 0.001, 0.0);
    const std::vector<Metric> before = m;
    MetricGradationOptions o;
    o.beta = 1.5;
    o.t = t;
    const MetricGradationResult r = limit_metric_gradation(points, edges, m, o);
    CHECK(r.converged);
    CHECK(r.sweeps >= 1);
    CHECK(r.max_gradation <= 1.01 * o.beta);
    for (const auto& e : edges) CHECK(edge_gradation(m[e[0]], m[e[1]], points[e[1]] - points[e[0]]) <= 1.01 * o.beta);
    for (std::size_t i = 0; i < m.size(); ++i)
      for (Vec2 v : {Vec2{1, 0}, Vec2{0, 1}, Vec2{1, 1}, Vec2{1, -2}})
        CHECK(m[i].quad(v) >= before[i].quad(v) * (1 - 1e-12));
    CHECK(same(m[small], before[small], 1e-15));
    // The neighbours had to shrink: at distance 1/11 with beta = 1.5 the size is far below 0.1.
    CHECK(eigen(m[small + 1]).lambda2 > 100.0 * 1.5);
  }
  // Anisotropic metrics of random shapes also end within beta in metric space.
  std::vector<Metric> m;
  for (std::size_t i = 0; i < points.size(); ++i)
    m.push_back(metric_from_sizes(0.02 + 0.1 * ((i * 37) % 11) / 11.0, 0.005 + 0.05 * ((i * 17) % 7) / 7.0,
                                  ((i * 53) % 13) * 15 * kDeg));
  MetricGradationOptions o;
  o.beta = 2.0;
  o.t = 0.0;
  const MetricGradationResult r = limit_metric_gradation(points, edges, m, o);
  CHECK(r.converged);
  CHECK(r.max_gradation <= 1.01 * 2.0);
}

TEST_CASE("limit_metric_gradation sweeps both ways and grows in metric space by default", "[metric][gradation]") {
  // A chain of 60 points along x, 0.01 apart, the last one a hundred times finer than the rest and
  // stretched (aspect 20): the edges come in index order, so the small metric has to travel against it.
  const int n = 60;
  std::vector<Vec2> points;
  std::vector<std::array<int, 2>> edges;
  for (int i = 0; i < n; ++i) points.push_back({0.01 * i, 0.0});
  for (int i = 0; i + 1 < n; ++i) edges.push_back({i, i + 1});
  std::vector<Metric> m(n, metric_from_sizes(0.5, 0.5, 0.0));
  m[n - 1] = metric_from_sizes(0.1, 0.005, 0.0);  // h_x = 0.1, h_y = 0.005
  const MetricGradationOptions defaults;
  CHECK(defaults.t == 0.0);
  const MetricGradationResult r = limit_metric_gradation(points, edges, m, defaults);
  CHECK(r.converged);
  // One sweep backward carries the small metric down the whole chain; a forward sweep then finds
  // nothing left to do. Sweeping forward only, it would move one edge a sweep.
  CHECK(r.sweeps <= 2);
  CHECK(r.max_gradation <= 1.01 * defaults.beta);
  // In metric space the spread metric keeps the shape of the small one: where it dominates, its
  // aspect ratio stays 20 (in physical space it would round off towards 1).
  for (int i : {n - 2, n - 5, n - 10}) {
    const MetricEigen e = eigen(m[i]);
    CHECK(std::sqrt(e.lambda1 / e.lambda2) == Approx(20.0).epsilon(1e-9));
  }
}

TEST_CASE("limit_metric_gradation refuses bad options naming them", "[metric][gradation]") {
  std::vector<Vec2> p{{0, 0}, {1, 0}};
  std::vector<Metric> m(2);
  MetricGradationOptions o;
  o.beta = 1.0;
  CHECK_THAT(error_message<InputError>([&] { limit_metric_gradation(p, {{0, 1}}, m, o); }), Contains("beta = 1"));
  o.beta = 1.5;
  o.t = 2.0;
  CHECK_THAT(error_message<InputError>([&] { limit_metric_gradation(p, {{0, 1}}, m, o); }), Contains("t = 2"));
}
