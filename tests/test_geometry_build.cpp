// build_geometry(): derived data against hand-computed values and every validation error.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "core/errors.hpp"
#include "geometry/geometry.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;

namespace {

RawCurve curve(std::vector<Vec2> points, std::string name = "", int line = 1) {
  RawCurve c;
  c.name = std::move(name);
  c.points = std::move(points);
  c.file = "test.crv";
  c.line = line;
  return c;
}

// Closed axis-aligned square as one curve, counter-clockwise from its lower-left corner.
RawCurve square(double x0, double y0, double side, std::string name = "") {
  return curve({{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}, {x0, y0}}, std::move(name));
}

std::vector<RawCurve> unit_square_of_four() {
  return {curve({{0, 0}, {1, 0}}), curve({{1, 0}, {1, 1}}), curve({{1, 1}, {0, 1}}), curve({{0, 1}, {0, 0}})};
}

}  // namespace

TEST_CASE("unit square of four curves", "[geometry]") {
  const Geometry g = build_geometry(unit_square_of_four());
  REQUIRE(g.curves.size() == 4);
  CHECK(g.curves[2].name == "curve2");
  CHECK(g.area == 1.0);
  REQUIRE(g.loops.size() == 1);
  CHECK(g.loops[0].curves == std::vector<int>{0, 1, 2, 3});
  CHECK(g.loops[0].reversed == std::vector<std::uint8_t>{0, 0, 0, 0});
  CHECK(g.loops[0].signed_area == 1.0);
  CHECK(g.loops[0].depth == 0);
  REQUIRE(g.critical.size() == 4);
  // First entry: the start of curve 0, where curve 3 ends.
  CHECK(g.critical[0].p == Vec2{0, 0});
  CHECK(g.critical[0].curves == std::vector<int>{0, 3});
  CHECK(g.critical[0].indices == std::vector<int>{0, 1});
  CHECK(g.critical[1].p == Vec2{1, 0});
  CHECK(g.critical[1].curves == std::vector<int>{0, 1});
  REQUIRE(g.segments.size() == 4);
  CHECK(g.curves[3].first_segment == 3);
  CHECK(g.segments[3].curve == 3);
  CHECK(g.segments[3].index == 0);
  CHECK(g.segments[3].length == 1.0);
  CHECK(g.curves[1].arc == std::vector<double>{0.0, 1.0});
  CHECK(g.curves[1].critical == std::vector<std::uint8_t>{1, 1});
  CHECK(g.extents.lo == Vec2{0, 0});
  CHECK(g.extents.hi == Vec2{1, 1});
}

TEST_CASE("curve ends within the join tolerance are snapped to the first end seen", "[geometry]") {
  auto raw = unit_square_of_four();
  raw[1].points[0] = {1 + 1e-12, -1e-12};  // within 1e-9 * sqrt(2)
  raw[3].points[1] = {1e-11, 0};
  const Geometry g = build_geometry(raw);
  CHECK(g.curves[1].points[0] == Vec2{1, 0});
  CHECK(g.curves[3].points[1] == Vec2{0, 0});
  CHECK(g.loops.size() == 1);

  GeometryOptions strict;
  strict.join_tolerance = 0.0;
  CHECK_THROWS_WITH(build_geometry(raw, strict), Contains("loop does not close"));
}

TEST_CASE("square with a square hole", "[geometry]") {
  const Geometry g = build_geometry({square(0, 0, 4, "outer"), square(1, 1, 1, "hole")});
  CHECK(g.area == 15.0);
  REQUIRE(g.loops.size() == 2);
  CHECK(g.loops[0].depth == 0);
  CHECK(g.loops[1].depth == 1);
  CHECK(g.loops[0].signed_area == 16.0);
  CHECK(g.loops[1].signed_area == 1.0);
  // Each closed curve: its start/end joint plus three 90-degree corners.
  CHECK(g.critical.size() == 8);
  CHECK(g.critical[0].curves == std::vector<int>{0, 0});
  CHECK(g.critical[0].indices == std::vector<int>{0, 4});
  CHECK(g.curves[0].critical == std::vector<std::uint8_t>{1, 1, 1, 1, 1});
  CHECK(g.curves[0].arc == std::vector<double>{0, 4, 8, 12, 16});
}

TEST_CASE("circle split into two semicircles, one traversed reversed", "[geometry]") {
  const int n = 64;  // segments around the whole circle
  std::vector<Vec2> upper, lower;
  for (int k = 0; k <= n / 2; ++k) {
    const double t = 2 * std::numbers::pi * k / n;
    upper.push_back({std::cos(t), std::sin(t)});
    lower.push_back({std::cos(t), -std::sin(t)});  // also from (1, 0) to (-1, 0), below
  }
  upper.back() = {-1, 0};
  lower.back() = {-1, 0};
  const Geometry g = build_geometry({curve(upper), curve(lower)});
  REQUIRE(g.loops.size() == 1);
  CHECK(g.loops[0].reversed == std::vector<std::uint8_t>{0, 1});
  const double polygon_area = 0.5 * n * std::sin(2 * std::numbers::pi / n);
  CHECK(g.loops[0].signed_area == Approx(polygon_area).epsilon(1e-12));
  CHECK(g.area == Approx(polygon_area).epsilon(1e-12));
  // 5.6-degree turns stay below the 30-degree corner threshold: only the two joints are critical.
  CHECK(g.critical.size() == 2);
  CHECK(g.curves[0].length() == Approx(n * std::sin(std::numbers::pi / n)).epsilon(1e-12));
  GeometryOptions fine;
  fine.corner_angle_deg = 5.0;
  CHECK(build_geometry({curve(upper), curve(lower)}, fine).critical.size() == 2 + 2 * (n / 2 - 1));
}

TEST_CASE("a single closed curve with one sharp corner among gentle bends", "[geometry]") {
  const Geometry g = build_geometry({curve({{0, 0}, {1, 0}, {2, 0.1}, {3, 0}, {3, 2}, {0, 2}, {0, 0}})});
  // Turns at (1,0) and (2,0.1) are 5.7 and 11.4 degrees; the others are about 90 degrees.
  CHECK(g.curves[0].critical == std::vector<std::uint8_t>{1, 0, 0, 1, 1, 1, 1});
  CHECK(g.critical.size() == 4);
  CHECK(g.area == Approx(5.9).epsilon(1e-14));
  CHECK(g.loops[0].signed_area == Approx(5.9).epsilon(1e-14));
}

TEST_CASE("nesting depth of three nested squares and a separate one", "[geometry]") {
  const Geometry g = build_geometry({square(0, 0, 6), square(1, 1, 4), square(2, 2, 2), square(10, 0, 1),
                                     curve({{10, 3}, {9, 4}, {10, 5}, {10, 3}})});
  REQUIRE(g.loops.size() == 5);
  CHECK(g.loops[0].depth == 0);
  CHECK(g.loops[1].depth == 1);
  CHECK(g.loops[2].depth == 2);
  CHECK(g.loops[3].depth == 0);
  CHECK(g.loops[4].depth == 0);
  CHECK(g.loops[4].signed_area == -1.0);  // clockwise triangle
  CHECK(g.area == 36.0 - 16.0 + 4.0 + 1.0 + 1.0);
}

TEST_CASE("a polygon with thousands of segments passes the intersection check", "[geometry]") {
  const int n = 5003;
  std::vector<Vec2> pts;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * std::numbers::pi * k / n;
    const double r = 1 + 0.3 * std::sin(7 * t);
    pts.push_back({r * std::cos(t), r * std::sin(t)});
  }
  pts.push_back(pts[0]);
  const Geometry g = build_geometry({curve(pts), square(-0.1, -0.1, 0.2)});
  CHECK(g.segments.size() == static_cast<std::size_t>(n + 4));
  CHECK(g.loops[1].depth == 1);
}

TEST_CASE("geometry errors: point counts and values", "[geometry]") {
  CHECK_THROWS_AS(build_geometry(std::vector<RawCurve>{}), GeometryError);
  CHECK_THROWS_WITH(build_geometry({curve({{0, 0}}, "lonely", 7)}),
                    Contains("test.crv:7") && Contains("curve 'lonely'") && Contains("1 point"));
  auto raw = unit_square_of_four();
  raw[2].points[1].y = std::nan("");
  CHECK_THROWS_WITH(build_geometry(raw),
                    Contains("test.crv:2") && Contains("curve 'curve2'") && Contains("non-finite"));
  raw = unit_square_of_four();
  raw[0].points[1].x = INFINITY;
  CHECK_THROWS_WITH(build_geometry(raw), Contains("point 1") && Contains("inf"));
}

TEST_CASE("geometry errors: repeated point", "[geometry]") {
  RawCurve c = curve({{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 0}}, "rep", 10);
  CHECK_THROWS_WITH(build_geometry({c}), Contains("test.crv:12") && Contains("curve 'rep'") && Contains("segment 1") &&
                                             Contains("zero length") && Contains("(1, 0)"));
}

TEST_CASE("geometry errors: loop does not close", "[geometry]") {
  auto raw = unit_square_of_four();
  raw.pop_back();
  CHECK_THROWS_WITH(build_geometry(raw), Contains("loop does not close") && Contains("curve 'curve0'") &&
                                             Contains("test.crv:1") && Contains("(0, 0)"));
}

TEST_CASE("geometry errors: three curve ends at one point", "[geometry]") {
  auto raw = unit_square_of_four();
  raw.push_back(curve({{0, 0}, {0.5, 0.5}, {1, 1}}, "diagonal"));
  CHECK_THROWS_WITH(build_geometry(raw),
                    Contains("3 curve ends meet at (0, 0)") && Contains("'diagonal'") && Contains("'curve3'"));
}

TEST_CASE("geometry errors: self-intersecting curve", "[geometry]") {
  // A bow tie: segment 0 crosses segment 2 at (1, 1).
  CHECK_THROWS_WITH(build_geometry({curve({{0, 0}, {2, 2}, {2, 0}, {0, 2}, {0, 0}}, "bow", 20)}),
                    Contains("curve 'bow' intersects itself") && Contains("segment 0 (test.crv:20)") &&
                        Contains("segment 2 (test.crv:22)") && Contains("(1, 1)"));
  // Folding back along itself at an interior vertex.
  CHECK_THROWS_WITH(build_geometry({curve({{0, 0}, {2, 0}, {1, 0}, {1, 1}, {0, 0}}, "fold")}),
                    Contains("curve 'fold' intersects itself"));
}

TEST_CASE("geometry errors: two crossing curves", "[geometry]") {
  CHECK_THROWS_WITH(build_geometry({square(0, 0, 2, "a"), square(1, 1, 2, "b")}),
                    Contains("curves intersect") && Contains("curve 'a' segment 1") &&
                        Contains("curve 'b' segment 0") && Contains("(2, 1)"));
}

TEST_CASE("geometry errors: T-junction and shared vertices", "[geometry]") {
  // A triangle whose corner touches the middle of the square's bottom edge.
  CHECK_THROWS_WITH(
      build_geometry({square(0, 0, 2, "sq"), curve({{1, 0}, {1.5, -1}, {0.5, -1}, {1, 0}}, "tri")}),
      Contains("curves intersect") && Contains("'sq' segment 0") && Contains("'tri' segment") && Contains("(1, 0)"));
  // Two loops touching at a vertex: neither is a joint of two curve ends only.
  CHECK_THROWS_WITH(build_geometry({square(0, 0, 1, "p"), curve({{0, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 1}}, "q")}),
                    Contains("intersect"));
  // Two curves running over each other away from their joint.
  CHECK_THROWS_WITH(build_geometry({curve({{0, 0}, {2, 0}}, "x"), curve({{2, 0}, {1, 0}, {0, 0}}, "y")}),
                    Contains("curves intersect") && Contains("'x'") && Contains("'y'"));
}

TEST_CASE("hole points must lie in a hole", "[geometry]") {
  const std::vector<RawCurve> raw = {square(0, 0, 4, "outer"), square(1, 1, 1, "hole")};
  const Geometry g = build_geometry(raw, {{{1.5, 1.5}, "h.poly", 3}, {{9, 9}, "h.poly", 4}});
  CHECK(g.hole_points.size() == 2);
  CHECK_THROWS_WITH(build_geometry(raw, {{{3, 3}, "h.poly", 5}}),
                    Contains("h.poly:5") && Contains("(3, 3)") && Contains("inside the domain"));
  CHECK_THROWS_WITH(build_geometry(raw, {{{1.5, 1}, "h.poly", 6}}),
                    Contains("h.poly:6") && Contains("on the boundary"));
}

TEST_CASE("geometry options are checked", "[geometry]") {
  GeometryOptions bad;
  bad.join_tolerance = 2;
  CHECK_THROWS_WITH(build_geometry(unit_square_of_four(), bad), Contains("join tolerance 2"));
  bad = {};
  bad.corner_angle_deg = std::nan("");
  CHECK_THROWS_WITH(build_geometry(unit_square_of_four(), bad), Contains("corner angle nan"));
}
