// Tests of geometry.curves = "smooth": the centripetal Catmull-Rom curves through the input points
// (accuracy on a circle, corners kept at critical points, C1 across smooth joints) and their dense
// polyline (within its chord tolerance, same curves and critical points, crossings refused).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry/smooth_curve.hpp"
#include "spacing/spacing_field.hpp"
#include "geometry_fixtures.hpp"

using namespace pdmesh;

namespace {

// A closed circle of radius r and n segments as one curve starting at angle a0.

// Largest |distance from the origin - r| over the smooth curve, sampled 200 times per piece.
double radial_error(const SmoothCurves& s, int curve, double r) {
  double worst = 0.0;
  const Curve& c = s.geometry().curves[static_cast<std::size_t>(curve)];
  for (int k = 0; k < c.segment_count(); ++k)
    for (int j = 0; j <= 200; ++j) worst = std::max(worst, std::fabs(norm(s.at(curve, k, j / 200.0)) - r));
  return worst;
}

}  // namespace

TEST_CASE("a smooth curve through points of a circle lies within the chord error of the circle", "[smooth]") {
  for (const int n : {16, 24, 48}) {
    const Geometry g = build_geometry({fixtures::circle_curve(2.0, n)});
    const SmoothCurves s(g, 30.0);
    const double chord_error = 2.0 * (1.0 - std::cos(std::numbers::pi / n));  // the polyline's sagitta
    const double err = radial_error(s, 0, 2.0);
    INFO(n << " points: smooth curve radial error " << err << ", polyline chord error " << chord_error);
    // Measured: 0.029 (n = 16), 0.013 (24), 0.0032 (48) of the chord error, so the curve's own
    // error falls as h^4 where the polyline's falls as h^2.
    CHECK(err < 0.05 * chord_error);
  }
}

TEST_CASE("the dense polyline is within its chord tolerance of the smooth curve", "[smooth]") {
  const Geometry g = build_geometry({fixtures::circle_curve(2.0, 16)});
  const SmoothCurves s(g, 30.0);
  const double q = 0.1;
  DenseOptions options;
  const DenseGeometry d = make_dense_geometry(
      s, [q](Vec2) { return q; }, options);
  const GeometryTree tree(d.geometry);
  const double tol = options.tolerance * q;  // h = min(q, segment length) = q here
  double worst = 0.0;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j <= 400; ++j) worst = std::max(worst, tree.closest(s.at(0, k, j / 400.0)).distance);
  INFO("dense segments " << d.geometry.segments.size() << ", worst distance " << worst << ", tolerance " << tol);
  CHECK(worst <= tol * (1.0 + 1e-9));
  // Not absurdly fine either: about sqrt(8 tol R) long segments (R = 2): 2 pi R / 0.04 = 314.
  CHECK(d.geometry.segments.size() < 800);
  // The input points are vertices of the dense curve, and every dense segment knows its source.
  for (int i = 0; i <= 16; ++i)
    CHECK(d.geometry.curves[0].points[static_cast<std::size_t>(d.vertex[0][static_cast<std::size_t>(i)])] ==
          g.curves[0].points[static_cast<std::size_t>(i)]);
  REQUIRE(d.source.size() == d.geometry.segments.size());
  for (std::size_t j = 0; j < d.source.size(); ++j) {
    const Segment& in = g.segments[static_cast<std::size_t>(d.source[j])];
    // A dense segment lies within the sagitta band of its input segment.
    CHECK(dist(d.geometry.segments[j].a, in.a) <= in.length + 1e-12);
  }
}

TEST_CASE("smooth curves keep corners at critical points and stay straight on straight sections", "[smooth]") {
  // A square of four curves (corner joints) with 3 points a side, and a bent curve: its interior
  // vertex turns 60 degrees (critical), the others 10 degrees.
  std::vector<RawCurve> raw;
  const Vec2 c[4] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  for (int k = 0; k < 4; ++k) {
    const Vec2 a = c[k], b = c[(k + 1) % 4];
    raw.push_back({"side" + std::to_string(k), {a, 0.5 * (a + b), b}, "test", 1, {}});
  }
  const Geometry square = build_geometry(std::move(raw));
  const SmoothCurves s(square, 30.0);
  for (int curve = 0; curve < 4; ++curve)
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j <= 10; ++j) {
        const Vec2 p = s.at(curve, k, j / 10.0);
        CHECK(std::min({std::fabs(p.x), std::fabs(p.x - 4), std::fabs(p.y), std::fabs(p.y - 4)}) < 1e-12);
      }
  const DenseGeometry d = make_dense_geometry(s, [](Vec2) { return 0.5; });
  CHECK(d.geometry.segments.size() == square.segments.size());  // nothing to add on straight lines

  // An open polyline with a 60-degree corner, closed by a straight curve.
  const double t = std::numbers::pi / 18;  // 10 degrees
  std::vector<Vec2> bent{{0, 0}};
  double angle = 0.0;
  for (int i = 1; i <= 8; ++i) {
    bent.push_back(bent.back() + Vec2{std::cos(angle), std::sin(angle)});
    angle += i == 4 ? std::numbers::pi / 3 : t;
  }
  std::vector<RawCurve> raw2{{"bent", bent, "test", 1, {}}, {"close", {bent.back(), bent.front()}, "test", 20, {}}};
  const Geometry g = build_geometry(std::move(raw2));
  REQUIRE(g.curves[0].critical[4] == 1);
  const SmoothCurves sb(g, 30.0);
  // Tangents on both sides of the corner keep the 60-degree turn (within the smoothing of the
  // neighbouring 10-degree vertices); at a smooth vertex they agree.
  const Vec2 in = sb.derivative(0, 3, 1.0), out = sb.derivative(0, 4, 0.0);
  const double corner = std::atan2(std::fabs(cross(in, out)), dot(in, out));
  CHECK(corner > std::numbers::pi / 4);
  const Vec2 in2 = sb.derivative(0, 1, 1.0), out2 = sb.derivative(0, 2, 0.0);
  CHECK(std::fabs(cross(in2, out2)) < 1e-12 * norm(in2) * norm(out2));
  // The dense geometry has the same critical points, in the same order, at the same places.
  const DenseGeometry dg = make_dense_geometry(sb, [](Vec2) { return 0.2; });
  REQUIRE(dg.geometry.critical.size() == g.critical.size());
  for (std::size_t k = 0; k < g.critical.size(); ++k) {
    CHECK(dg.geometry.critical[k].p == g.critical[k].p);
    for (std::size_t j = 0; j < g.critical[k].curves.size(); ++j) {
      const int curve = dg.geometry.critical[k].curves[j];
      const auto idx = static_cast<std::size_t>(dg.geometry.critical[k].indices[j]);
      CHECK(dg.geometry.curves[static_cast<std::size_t>(curve)].points[idx] == g.critical[k].p);
      CHECK(dg.geometry.curves[static_cast<std::size_t>(curve)].critical[idx] == 1);
    }
  }
  std::size_t flagged = 0;
  for (const Curve& curve : dg.geometry.curves)
    for (const auto f : curve.critical) flagged += f;
  CHECK(flagged == 5);  // 2 joints (2 flags each) + the corner
  CHECK(dg.geometry.loops.size() == 1);
}

TEST_CASE("smooth curves are C1 across a joint whose turn is below the corner angle", "[smooth]") {
  // A circle of two semicircle curves: the joints are critical (fixed nodes) but not corners.
  std::vector<RawCurve> raw;
  for (int half = 0; half < 2; ++half) {
    RawCurve c{half == 0 ? "upper" : "lower", {}, "test", 1, {}};
    for (int i = 0; i <= 8; ++i) {
      const double a = std::numbers::pi * (half + i / 8.0);
      c.points.push_back({std::cos(a), std::sin(a)});
    }
    c.points.front() = {half == 0 ? 1.0 : -1.0, 0.0};
    c.points.back() = {half == 0 ? -1.0 : 1.0, 0.0};
    raw.push_back(std::move(c));
  }
  const Geometry g = build_geometry(std::move(raw));
  const SmoothCurves s(g, 30.0);
  // At (-1, 0): end of the upper curve, start of the lower one.
  const Vec2 in = s.derivative(0, 7, 1.0), out = s.derivative(1, 0, 0.0);
  CHECK(std::fabs(cross(in, out)) < 1e-12 * norm(in) * norm(out));
  CHECK(dot(in, out) > 0.0);
  CHECK(radial_error(s, 0, 1.0) < 0.05 * (1.0 - std::cos(std::numbers::pi / 8)));
  // With a corner angle below the joints' 22.5-degree turn, each curve ends on its own: its end
  // tangent no longer depends on the other curve (for a circle it is still the circle's tangent).
  const SmoothCurves sharp(g, 20.0);
  Geometry moved = g;
  moved.curves[1].points[1] = 0.9 * moved.curves[1].points[1];
  const SmoothCurves joined_moved(moved, 30.0), sharp_moved(moved, 20.0);
  CHECK(sharp.derivative(0, 7, 1.0) == sharp_moved.derivative(0, 7, 1.0));
  CHECK(!(s.derivative(0, 7, 1.0) == joined_moved.derivative(0, 7, 1.0)));
}

TEST_CASE("smooth curves that cross another curve are refused as a geometry error", "[smooth]") {
  // A 16-gon hole of radius 1 whose vertices sit at 11.25 + 22.5k degrees: its polyline reaches
  // x = 0.981, its smooth curve x = 1.0. The outer boundary's right side at x = 0.99 passes between.
  RawCurve outer{"outer", {{-2, -2}, {0.99, -2}, {0.99, 2}, {-2, 2}, {-2, -2}}, "test", 1, {}};
  const Geometry g = build_geometry({outer, fixtures::circle_curve(1.0, 16, std::numbers::pi / 16, "hole")});
  const SmoothCurves s(g, 30.0);
  CHECK_THROWS_AS(make_dense_geometry(s, [](Vec2) { return 0.1; }), GeometryError);
  try {
    make_dense_geometry(s, [](Vec2) { return 0.1; });
  } catch (const GeometryError& e) {
    CHECK_THAT(e.what(), Catch::Contains("geometry.curves = \"smooth\"") && Catch::Contains("intersect"));
  }
}
