// Geometry file readers (.crv/.dat, .poly) and read_geometry(): good files and every error case.
#include <catch2/catch.hpp>

#include <filesystem>

#include "core/errors.hpp"
#include "geometry/curve_reader.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/poly_reader.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;

namespace {

std::string data(const std::string& name) { return std::string(PDMESH_SOURCE_DIR "/tests/data/geometry/") + name; }

const std::string k30p30n = PDMESH_SOURCE_DIR "/../shared/data/30p30n/2010_30p30n_thik_te_18inches.crv.dat";
const std::string k30p30nExcerpt = data("30p30n_flap.crv");

}  // namespace

TEST_CASE("crv reader: unit square with comments and optional z", "[geometry]") {
  const auto raw = read_curve_file(data("unit_square.crv"));
  REQUIRE(raw.size() == 4);
  CHECK(raw[0].points.size() == 2);
  CHECK(raw[0].line == 3);
  CHECK(raw[0].lines == std::vector<int>{3, 4});
  CHECK(raw[1].lines == std::vector<int>{7, 8});
  CHECK(raw[2].points[1] == Vec2{0, 1});
  CHECK(raw[0].file == data("unit_square.crv"));
  const Geometry g = build_geometry(raw);
  CHECK(g.area == 1.0);
  CHECK(g.critical.size() == 4);
}

TEST_CASE("crv reader: the 30P30N high-lift airfoil makes 3 clockwise loops of 11 curves", "[geometry]") {
  const std::string path = std::filesystem::exists(k30p30n) ? k30p30n : k30p30nExcerpt;
  const auto raw = read_curve_file(path);
  const Geometry g = build_geometry(raw);
  if (path == k30p30n) {
    REQUIRE(raw.size() == 11);
    CHECK(raw[3].points.size() == 401);
    REQUIRE(g.loops.size() == 3);
    CHECK(g.loops[0].curves == std::vector<int>{0, 1, 2, 3, 4});
    CHECK(g.loops[1].curves == std::vector<int>{5, 6, 7});
    CHECK(g.loops[2].curves == std::vector<int>{8, 9, 10});
    CHECK(g.segments.size() == 1067u - 11u);  // 1078 lines - 11 count lines = 1067 points
  }
  for (const Loop& loop : g.loops) {
    CHECK(loop.signed_area < 0);  // clockwise
    CHECK(loop.depth == 0);
  }
  CHECK(g.area > 0);
}

TEST_CASE("crv reader errors", "[geometry]") {
  CHECK_THROWS_WITH(read_curve_file(data("no_such_file.crv")), Contains("cannot read geometry file") &&
                                                                   Contains("no_such_file.crv") &&
                                                                   Contains("No such file or directory"));
  CHECK_THROWS_WITH(read_curve_file(data("")), Contains("directory"));
  CHECK_THROWS_WITH(read_curve_file(data("empty.crv")), Contains("empty.crv") && Contains("no curves"));
  CHECK_THROWS_WITH(read_curve_file(data("comments_only.crv")), Contains("no curves"));
  CHECK_THROWS_WITH(read_curve_file(data("garbage.crv")), Contains("garbage.crv:4") && Contains("not text"));
  CHECK_THROWS_WITH(read_curve_file(data("truncated.crv")), Contains("truncated.crv:4") &&
                                                                Contains("block of 5 points is truncated") &&
                                                                Contains("only 3 lines"));
  CHECK_THROWS_WITH(read_curve_file(data("negative_count.crv")),
                    Contains("negative_count.crv:1") && Contains("'-3' is negative"));
  CHECK_THROWS_WITH(read_curve_file(data("fractional_count.crv")),
                    Contains("fractional_count.crv:1") && Contains("'2.5' is not a non-negative integer"));
  CHECK_THROWS_WITH(read_curve_file(data("nan.crv")), Contains("nan.crv:3") && Contains("'nan' is not finite"));
  CHECK_THROWS_WITH(read_curve_file(data("inf.crv")), Contains("inf.crv:4") && Contains("'-inf' is not finite"));
  CHECK_THROWS_WITH(read_curve_file(data("huge.crv")), Contains("huge.crv:3") && Contains("'1e308' is too large"));
  CHECK_THROWS_WITH(read_curve_file(data("extra_tokens.crv")),
                    Contains("extra_tokens.crv:3") && Contains("extra text '7'"));
  CHECK_THROWS_WITH(read_curve_file(data("bad_number.crv")),
                    Contains("bad_number.crv:3") && Contains("'0x' is not a number"));
  CHECK_THROWS_WITH(read_curve_file(data("count_too_large.crv")),
                    Contains("count_too_large.crv:6") && Contains("found '2'") && Contains("line 1"));
  // A one-point curve reads fine; build_geometry rejects it with the file and line.
  CHECK_THROWS_WITH(build_geometry(read_curve_file(data("one_point.crv"))),
                    Contains("one_point.crv:2") && Contains("1 point"));
}

TEST_CASE("crv reader: the 30P30N flap excerpt is one clockwise loop", "[geometry]") {
  const Geometry g = build_geometry(read_curve_file(k30p30nExcerpt));
  REQUIRE(g.curves.size() == 3);
  REQUIRE(g.loops.size() == 1);
  CHECK(g.loops[0].signed_area < 0);
  CHECK(g.segments.size() == 100u + 100u + 4u);
  CHECK(g.critical.size() >= 3);
}

TEST_CASE("poly reader: square with a hole, hole point and a regional attribute", "[geometry]") {
  const PolyFile poly = read_poly_file(data("square_with_hole.poly"));
  REQUIRE(poly.curves.size() == 2);
  CHECK(poly.curves[0].points.size() == 5);
  CHECK(poly.curves[0].points.front() == poly.curves[0].points.back());
  CHECK(poly.curves[1].points[1] == Vec2{2, 1});
  CHECK(poly.curves[1].lines == std::vector<int>{7, 8, 9, 10, 7});
  REQUIRE(poly.holes.size() == 1);
  CHECK(poly.holes[0].p == Vec2{1.5, 1.5});
  CHECK(poly.holes[0].line == 21);
  const Geometry g = read_geometry({data("square_with_hole.poly")}, {"outer", "hole"});
  CHECK(g.area == 15.0);
  CHECK(g.curves[1].name == "hole");
  CHECK(g.hole_points.size() == 1);
  CHECK(g.loops[1].depth == 1);
}

TEST_CASE("poly reader: one curve per boundary marker, chained in loop order", "[geometry]") {
  const PolyFile poly = read_poly_file(data("square_sides.poly"));
  REQUIRE(poly.curves.size() == 4);
  CHECK(poly.curves[0].points == std::vector<Vec2>{{1, 1}, {0, 1}});  // marker 12, first in the file
  CHECK(poly.curves[1].points == std::vector<Vec2>{{0, 0}, {1, 0}});  // marker 10
  const Geometry g = build_geometry(poly.curves);
  CHECK(g.loops[0].curves == std::vector<int>{0, 2, 1, 3});
  CHECK(g.loops[0].signed_area == 1.0);
  CHECK(g.critical.size() == 4);
}

TEST_CASE("poly reader: segments of one marker forming a cycle make one closed curve", "[geometry]") {
  const PolyFile poly = read_poly_file(data("two_chains.poly"));
  REQUIRE(poly.curves.size() == 1);
  CHECK(poly.curves[0].points == std::vector<Vec2>{{0, 0}, {1, 0}, {2, 0}, {2, 2}, {0, 2}, {0, 0}});
  const Geometry g = build_geometry(poly.curves);
  CHECK(g.area == 4.0);
  CHECK(g.critical.size() == 4);  // the straight vertex (1, 0) is no corner
}

TEST_CASE("poly reader errors", "[geometry]") {
  CHECK_THROWS_WITH(read_poly_file(data("missing_vertex.poly")), Contains("missing_vertex.poly:7") &&
                                                                     Contains("segment 2 refers to vertex 9") &&
                                                                     Contains("1 to 3"));
  CHECK_THROWS_WITH(read_poly_file(data("node_file.poly")),
                    Contains("node_file.poly:1") && Contains(".node") && Contains("not support"));
  CHECK_THROWS_WITH(read_poly_file(data("three_d.poly")), Contains("three_d.poly:1") && Contains("dimension '3'"));
  CHECK_THROWS_WITH(read_poly_file(data("short_vertices.poly")),
                    Contains("short_vertices.poly:6") && Contains("a vertex line should have 3 values, found 2"));
  CHECK_THROWS_WITH(read_poly_file(data("no_hole_line.poly")),
                    Contains("no_hole_line.poly:10") && Contains("hole count line"));
  CHECK_THROWS_WITH(read_poly_file(data("empty.crv")), Contains("empty"));
  // Triangle's rule: the hole point removes the only face, and the convex hull is that same face.
  CHECK_THROWS_WITH(read_geometry({data("hole_in_domain.poly")}, {}),
                    Contains("hole_in_domain.poly") && Contains("no area outside the holes") && Contains("line 12"));
}

TEST_CASE("read_geometry: extensions and curve names", "[geometry]") {
  const Geometry g = read_geometry({data("unit_square.crv")}, {"bottom", "right", "top", "left"});
  CHECK(g.curves[3].name == "left");
  CHECK(read_geometry({data("unit_square.crv")}, {}).curves[0].name == "curve0");
  CHECK_THROWS_WITH(read_geometry({data("unit_square.crv")}, {"a", "b"}),
                    Contains("2 curve names given") && Contains("4 curves") && Contains("unit_square.crv: 4 curves"));
  CHECK_THROWS_WITH(read_geometry({data("unit_square.crv")}, {"a", "b", "a", "c"}), Contains("'a' is given twice"));
  CHECK_THROWS_WITH(read_geometry({data("square.stl")}, {}),
                    Contains("square.stl") && Contains("'.stl'") && Contains(".crv, .dat, .poly"));
  CHECK_THROWS_AS(read_geometry({}, {}), InputError);
  // Two files together: the unit square shares the corner (0, 0) with the square with a hole.
  CHECK_THROWS_WITH(read_geometry({data("square_with_hole.poly"), data("unit_square.crv")}, {}),
                    Contains("4 curve ends meet at (0, 0)") && Contains("unit_square.crv:15"));
}
