// Spacing fields: thesis eq. 3.6 against hand-computed values and its boundary limit; the
// muParser expression field against std::tanh; expression errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "core/errors.hpp"
#include "geometry/brute_force_queries.hpp"
#include "geometry_fixtures.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;

// The call throws InputError and its message matches.
#define CHECK_INPUT_ERROR(expr, matcher) \
  do {                                   \
    CHECK_THROWS_AS(expr, InputError);   \
    CHECK_THROWS_WITH(expr, matcher);    \
  } while (false)

namespace {

// Curve 0: (0,0)-(1,0), length 1. Curve 1: (-1,3)-(2,3), length 3.
Geometry two_parallel_segments() { return fixtures::make_geometry({{{0, 0}, {1, 0}}, {{-1, 3}, {2, 3}}}); }

}  // namespace

TEST_CASE("BoundarySpacing matches eq. 3.6 by hand", "[spacing]") {
  const Geometry g = two_parallel_segments();
  const GeometryTree tree(g);
  const BoundarySpacing q(tree);
  // Distances 1 and 2: q = (1/1 + 3/2) / (1/1 + 1/2) = 5/3.
  CHECK(q.at({0.5, 1.0}) == Approx(5.0 / 3.0).epsilon(1e-14));
  // Distances 2 and 1: q = (1/2 + 3/1) / (1/2 + 1/1) = 7/3.
  CHECK(q.at({0.5, 2.0}) == Approx(7.0 / 3.0).epsilon(1e-14));
  // Beyond the end of curve 0: distance to (0,0) is sqrt(2) from (-1,1); curve 1 at distance 2.
  const double d0 = std::sqrt(2.0), d1 = 2.0;
  CHECK(q.at({-1.0, 1.0}) == Approx((1 / d0 + 3 / d1) / (1 / d0 + 1 / d1)).epsilon(1e-14));
}

TEST_CASE("BoundarySpacing on the boundary is the segment length", "[spacing]") {
  const Geometry g = two_parallel_segments();
  const GeometryTree tree(g);
  const BoundarySpacing q(tree);
  CHECK(q.at({0.5, 0.0}) == 1.0);
  CHECK(q.at({0.0, 0.0}) == 1.0);
  CHECK(q.at({2.0, 3.0}) == 3.0);
  CHECK(q.at({0.25, 3.0}) == 3.0);
  // Approaching the boundary the field tends to the limit and stays finite for tiny distances.
  for (const double h : {1e-3, 1e-9, 1e-200, std::numeric_limits<double>::denorm_min()}) {
    const double v = q.at({0.5, h});
    REQUIRE(std::isfinite(v));
    CHECK(v == Approx(1.0).epsilon(3 * h + 1e-15));
  }
}

TEST_CASE("BoundarySpacing at a joint of two curves is the mean of their segment lengths", "[spacing]") {
  const Geometry g = fixtures::make_geometry({{{0, 0}, {1, 0}}, {{1, 0}, {1, 3}}});
  const GeometryTree tree(g);
  const BoundarySpacing q(tree);
  CHECK(q.at({1.0, 0.0}) == 2.0);
  // Just off the joint both curves stay close, so q stays near the mean, not 1 or 3: outside the
  // corner both distances are sqrt(2)e-9; below curve 0 they are 1e-9 and sqrt(2)e-9.
  CHECK(q.at({1.0 + 1e-9, -1e-9}) == Approx(2.0).epsilon(1e-12));
  const double r2 = std::sqrt(2.0);
  CHECK(q.at({1.0 - 1e-9, -1e-9}) == Approx((1 + 3 / r2) / (1 + 1 / r2)).epsilon(1e-6));
}

TEST_CASE("BoundarySpacing at a shared vertex uses the lowest-index segment", "[spacing]") {
  // One curve: segment 0 of length 1, segment 1 of length 2, meeting at (1,0).
  const Geometry g = fixtures::make_geometry({{{0, 0}, {1, 0}, {1, 2}}});
  const GeometryTree tree(g);
  const BoundarySpacing q(tree);
  CHECK(q.at({1.0, 0.0}) == 1.0);
  // Equidistant from both segments (on the bisector outside the corner): again segment 0.
  CHECK(q.at({2.0, -1.0}) == 1.0);
  CHECK(q.at({1.0, 1.0}) == 2.0);
}

TEST_CASE("BoundarySpacing of a uniformly segmented square is constant", "[spacing]") {
  // Thesis ch. 7: a 200 x 200 square with 40 boundary points, q = 20 everywhere.
  const Geometry g = fixtures::make_geometry({fixtures::rectangle({0, 0}, {200, 200}, 10, true)});
  const GeometryTree tree(g);
  const BoundarySpacing q(tree);
  std::mt19937_64 rng(42);
  for (int i = 0; i < 500; ++i) {
    const Vec2 p{200 * fixtures::unit(rng), 200 * fixtures::unit(rng)};
    CHECK(q.at(p) == Approx(20.0).epsilon(1e-13));
  }
}

TEST_CASE("BoundarySpacing with several curves: weights follow each curve's closest segment", "[spacing]") {
  const Geometry g = fixtures::square_with_hole();  // outer segments length 1, hole segments length 1
  const GeometryTree tree(g);
  const BoundarySpacing q(tree);
  CHECK(q.at({0.5, 0.5}) == Approx(1.0).epsilon(1e-14));
  const Geometry g2 = fixtures::make_geometry(
      {fixtures::rectangle({0, 0}, {4, 4}, 2, true), fixtures::rectangle({1.5, 1.5}, {2.5, 2.5}, 4, false)});
  const GeometryTree tree2(g2);
  const BoundarySpacing q2(tree2);
  // Outer segments length 2 at distance 0.5 (from (0.5, 2)), hole segments length 0.25 at distance 1.
  CHECK(q2.at({0.5, 2.0}) == Approx((2 / 0.5 + 0.25 / 1) / (1 / 0.5 + 1 / 1.0)).epsilon(1e-14));
}

TEST_CASE("BoundarySpacing equals eq. 3.6 from brute-force closest segments", "[spacing]") {
  for (const Geometry& g : {fixtures::circle_in_circle(), fixtures::multiscale(), fixtures::jagged_polygon(97, 5)}) {
    const GeometryTree tree(g);
    const BoundarySpacing q(tree);
    std::mt19937_64 rng(11);
    std::vector<ClosestHit> hits;
    for (int i = 0; i < 2000; ++i) {
      const Box& e = g.extents;
      const Vec2 p{e.lo.x + e.width() * fixtures::unit(rng), e.lo.y + e.height() * fixtures::unit(rng)};
      brute_force::closest_per_curve(g, p, hits);
      double num = 0, den = 0;
      for (const ClosestHit& h : hits) {
        num += g.segments[h.segment].length / h.distance;
        den += 1 / h.distance;
      }
      INFO("p = (" << p.x << ", " << p.y << ")");
      REQUIRE(q.at(p) == Approx(num / den).epsilon(1e-12));
    }
  }
}

TEST_CASE("SpacingField::at_many loops over at", "[spacing]") {
  const Geometry g = two_parallel_segments();
  const GeometryTree tree(g);
  const BoundarySpacing q(tree);
  const std::vector<Vec2> pts{{0.5, 1.0}, {0.5, 0.0}, {7, -3}};
  std::vector<double> out{99.0};
  q.at_many(pts, out);
  REQUIRE(out.size() == 3);
  for (std::size_t i = 0; i < pts.size(); ++i) CHECK(out[i] == q.at(pts[i]));
  q.at_many({}, out);
  CHECK(out.empty());
}

TEST_CASE("ExpressionSpacing evaluates thesis eq. 7.2", "[spacing]") {
  const ExpressionSpacing q("0.5 + 19.5*tanh(x/16)^2");
  for (const double x : {-100.0, -16.0, -1.0, 0.0, 0.3, 16.0, 50.0}) {
    const double t = std::tanh(x / 16);
    CHECK(q.at({x, 123.0}) == Approx(0.5 + 19.5 * t * t).epsilon(1e-14));
  }
  const ExpressionSpacing r("1 + x*x + 2*y + pi");
  CHECK(r.at({3, 4}) == Approx(1 + 9 + 8 + M_PI).epsilon(1e-15));
  std::vector<double> out;
  r.at_many({{0, 0}, {1, 1}}, out);
  REQUIRE(out.size() == 2);
  CHECK(out[1] == Approx(4 + M_PI));
}

TEST_CASE("ExpressionSpacing reports errors naming the expression", "[spacing]") {
  CHECK_INPUT_ERROR(ExpressionSpacing("1 +"), Contains("spacing expression '1 +'"));
  CHECK_INPUT_ERROR(ExpressionSpacing("2*z"), Contains("spacing expression '2*z'"));
  CHECK_INPUT_ERROR(ExpressionSpacing("sin(x"), Contains("sin(x"));
  CHECK_THROWS_AS(ExpressionSpacing(""), InputError);
  // Division by zero at the probe point (0, 0) is not a syntax error.
  const ExpressionSpacing inv("1/x");
  CHECK(inv.at({2, 0}) == 0.5);
  CHECK_INPUT_ERROR(inv.at({0, 5}), Contains("'1/x'") && Contains("(0, 5)") && Contains("inf"));
  const ExpressionSpacing lin("x - 1");
  CHECK_INPUT_ERROR(lin.at({0.5, 2}), Contains("(0.5, 2)") && Contains("-0.5"));
  CHECK_INPUT_ERROR(lin.at({1, 0}), Contains("gives 0"));
  const ExpressionSpacing root("sqrt(x)");
  CHECK_INPUT_ERROR(root.at({-1, 0}), Contains("nan"));
}
