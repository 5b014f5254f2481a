// The node-count estimate over the background field's leaves (init/node_estimate): the closed-form
// integral of 1/q^2 for a bilinear q against quadrature, and whole estimates against closed forms,
// a brute-force grid integral and the per-sample estimate over the exact field.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry_fixtures.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "init/node_estimate.hpp"
#include "spacing/background_field.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

namespace {

// Gauss-Legendre with 20 x 20 points per cell of an m x m split of [0,1]^2.
double quadrature(double q00, double q10, double q01, double q11) {
  const int m = 64, g = 8;
  // 8-point rule nodes and weights on [-1, 1].
  static const double t[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                              0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
  static const double w[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                              0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  double sum = 0.0;
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b)
      for (int i = 0; i < g; ++i)
        for (int j = 0; j < g; ++j) {
          const double u = (a + 0.5 * (t[i] + 1)) / m, v = (b + 0.5 * (t[j] + 1)) / m;
          const double q = (1 - v) * ((1 - u) * q00 + u * q10) + v * ((1 - u) * q01 + u * q11);
          sum += w[i] * w[j] * 0.25 / (m * m) / (q * q);
        }
  return sum;
}

using fixtures::line;
using fixtures::square;

RawCurve circle(const std::string& name, double r, int segments) {
  RawCurve c{name, {}, "test", 0, {}};
  for (int i = 0; i < segments; ++i) {
    const double t = 2.0 * std::numbers::pi * i / segments;
    c.points.push_back({r * std::cos(t), r * std::sin(t)});
  }
  c.points.push_back(c.points.front());
  return c;
}

}  // namespace

TEST_CASE("node estimate: integral of 1/q^2 over a bilinear cell, closed form against quadrature", "[init]") {
  CHECK(inverse_square_integral(2.0, 2.0, 2.0, 2.0) == Approx(0.25).epsilon(1e-15));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> spread(0.05, 3.0);
  for (int k = 0; k < 40; ++k) {
    const double q00 = spread(rng), q10 = spread(rng), q01 = spread(rng);
    // Every fourth case nearly separable (the series branch), the rest general.
    const double q11 = k % 4 == 0 ? q10 * q01 / q00 * (1 + 1e-5) : spread(rng);
    INFO("corners " << q00 << " " << q10 << " " << q01 << " " << q11);
    CHECK(inverse_square_integral(q00, q10, q01, q11) == Approx(quadrature(q00, q10, q01, q11)).epsilon(1e-9));
  }
}

TEST_CASE("node estimate over the background field: a constant-spacing square is the closed form", "[init]") {
  const double L = 7.3;
  const Geometry g = square(L, 13);
  const GeometryTree tree(g);
  const BoundarySpacing exact(tree);
  const BackgroundSpacing field(exact, tree);
  const double q = L / 13;
  const double closed_form = L * L * 2.0 / (std::sqrt(3.0) * q * q);
  CHECK(estimate_node_count(tree, field) == Approx(closed_form).epsilon(1e-3));
}

TEST_CASE("node estimate over the background field: a square with a square hole, boundary leaves cut by the hole",
          "[init]") {
  // Constant spacing (every segment 0.25 long), the hole's sides off the quadtree's grid lines.
  const double L = 8.0, l = 2.0, q = 0.25;
  std::vector<RawCurve> raw;
  const Vec2 outer[4] = {{0, 0}, {L, 0}, {L, L}, {0, L}};
  const Vec2 o{2.13, 3.37};
  const Vec2 hole[4] = {{o.x, o.y}, {o.x, o.y + l}, {o.x + l, o.y + l}, {o.x + l, o.y}};  // clockwise
  for (int k = 0; k < 4; ++k)
    raw.push_back({"outer" + std::to_string(k), line(outer[k], outer[(k + 1) % 4], 32), "test", 0, {}});
  for (int k = 0; k < 4; ++k)
    raw.push_back({"hole" + std::to_string(k), line(hole[k], hole[(k + 1) % 4], 8), "test", 0, {}});
  const Geometry g = build_geometry(std::move(raw));
  REQUIRE(g.area == Approx(L * L - l * l));
  const GeometryTree tree(g);
  const BoundarySpacing exact(tree);
  const BackgroundSpacing field(exact, tree);
  const double closed_form = (L * L - l * l) * 2.0 / (std::sqrt(3.0) * q * q);
  CHECK(estimate_node_count(tree, field) == Approx(closed_form).epsilon(2e-3));
  // Shifting the whole geometry changes nothing but rounding.
  std::vector<RawCurve> moved;
  for (const Curve& c : g.curves) {
    RawCurve r{c.name, {}, "test", 0, {}};
    for (const Vec2& p : c.points) r.points.push_back({p.x + 100.37, p.y - 41.9});
    moved.push_back(std::move(r));
  }
  const Geometry gm = build_geometry(std::move(moved));
  const GeometryTree tm(gm);
  const BoundarySpacing em(tm);
  CHECK(estimate_node_count(tm, BackgroundSpacing(em, tm)) == Approx(closed_form).epsilon(2e-3));
}

TEST_CASE("node estimate over the background field agrees with the per-sample estimate (circle in circle, annulus)",
          "[init]") {
  for (const double inner : {0.5, 1.0}) {
    std::vector<RawCurve> raw = {circle("outer", 10.0, inner == 0.5 ? 60 : 160), circle("inner", inner, 60)};
    const Geometry g = build_geometry(std::move(raw));
    const GeometryTree tree(g);
    const BoundarySpacing exact(tree);
    const BackgroundSpacing field(exact, tree);
    const double per_sample = estimate_node_count(tree, static_cast<const SpacingField&>(exact));
    const double leaves = estimate_node_count(tree, field);
    INFO("inner radius " << inner << ": per-sample " << per_sample << ", leaves " << leaves);
    CHECK(leaves == Approx(per_sample).epsilon(0.01));
  }
}

TEST_CASE("node count bound: not below the estimate, above it only by the boundary leaves' outside parts", "[init]") {
  // The annulus: boundary leaves on both circles, cut by curved segments; the bound counts them whole.
  std::vector<RawCurve> raw = {circle("outer", 10.0, 160), circle("inner", 1.0, 60)};
  const Geometry g = build_geometry(std::move(raw));
  const GeometryTree tree(g);
  const BoundarySpacing exact(tree);
  const BackgroundSpacing field(exact, tree);
  const double estimate = estimate_node_count(tree, field);
  const double bound = node_count_bound(field);
  INFO("estimate " << estimate << ", bound " << bound);
  CHECK(bound >= estimate);
  CHECK(bound < 1.2 * estimate);
  // A square with constant spacing: its boundary leaves are cut by straight sides.
  const Geometry s = square(7.3, 13);
  const GeometryTree st(s);
  const BoundarySpacing se(st);
  const BackgroundSpacing sf(se, st);
  CHECK(node_count_bound(sf) >= estimate_node_count(st, sf));
}
