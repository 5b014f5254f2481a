// Triangle's semantics for .poly files (geometry/poly_domain.cpp, geometry/planar_faces.cpp): which
// segments bound the domain and which are constraints, hole points, isolated vertices, regional
// attributes, the convex hull, and the notes; on Triangle's own examples (tests/data/triangle).
#include <algorithm>
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

#include "core/errors.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/planar_faces.hpp"
#include "geometry/poly_reader.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

std::string data(const std::string& name) { return std::string(PDMESH_SOURCE_DIR) + "/tests/data/" + name; }

int count_constraints(const PolyFile& poly, bool constraint) {
  return static_cast<int>(std::count_if(poly.curves.begin(), poly.curves.end(),
                                        [&](const RawCurve& c) { return c.constraint == constraint; }));
}

bool closed(const RawCurve& c) { return c.points.front() == c.points.back(); }

bool any_note(const PolyFile& poly, const std::string& text) {
  return std::any_of(poly.notes.begin(), poly.notes.end(),
                     [&](const std::string& n) { return n.find(text) != std::string::npos; });
}

}  // namespace

TEST_CASE("planar faces: a square with a diagonal, a dangling edge and a separate square inside", "[geometry]") {
  // 0..3: the square [0,4]^2; 4, 5: a dangling edge from corner 0; 6..9: the square [2.5,3.5]^2.
  const std::vector<Vec2> v{{0, 0}, {4, 0},     {4, 4},     {0, 4},     {1, 0.5},
                            {9, 9}, {2.5, 0.5}, {3.5, 0.5}, {3.5, 1.5}, {2.5, 1.5}};
  const std::vector<std::array<int, 2>> e{{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2},
                                          {0, 4}, {6, 7}, {7, 8}, {8, 9}, {9, 6}};
  const PlanarFaces f = planar_faces(v, e);
  REQUIRE(f.outer.size() == 3);  // two triangles and the small square
  // The outer square's sides have the unbounded face on their right, the diagonal two triangles.
  CHECK(f.sides[0][1] == -1);
  CHECK(f.sides[4][0] >= 0);
  CHECK(f.sides[4][1] >= 0);
  CHECK(f.sides[4][0] != f.sides[4][1]);
  CHECK(f.sides[5][0] == f.sides[5][1]);  // the dangling edge lies inside one face
  // The small square sits in the lower triangle, the one left of 0 -> 1.
  CHECK((f.sides[6][0] == f.sides[0][0] || f.sides[6][1] == f.sides[0][0]));
  CHECK(locate_face(f, v, e, {3, 1}) != f.sides[0][0]);
  CHECK(locate_face(f, v, e, {1.5, 0.2}) == f.sides[0][0]);
  CHECK(locate_face(f, v, e, {2, 2}) == -2);  // on the diagonal
  CHECK(locate_face(f, v, e, {5, 5}) == -1);
  CHECK(locate_face(f, v, e, {1, 3}) == f.sides[4][0]);  // upper-left triangle: left of 0 -> 2
}

TEST_CASE("poly semantics: a loop without a hole point is a constraint, regions and hole points", "[geometry]") {
  const PolyFile poly = read_poly_file(data("geometry/nested_no_hole.poly"));
  REQUIRE(poly.curves.size() == 2);
  CHECK_FALSE(poly.curves[0].constraint);  // the outer square bounds the domain
  CHECK(poly.curves[1].constraint);        // the inner one bounds a subdomain
  CHECK(closed(poly.curves[1]));
  // The hole point at (9, 9) removes nothing, the region at (-1, -1) is outside: both noted.
  CHECK(any_note(poly, "nested_no_hole.poly:23: hole point (9, 9) lies outside every loop"));
  CHECK(any_note(poly, "nested_no_hole.poly:28: region point (-1, -1) lies outside the domain"));
  // The even-odd rule would have made the inner square a hole: said, naming its first vertex and line.
  CHECK(any_note(poly, "nested_no_hole.poly:8: the face inside the loop through vertex 5 is meshed as a subdomain"));
  REQUIRE(poly.regions.size() == 2);
  CHECK(poly.regions[0].attribute == 10);
  CHECK(poly.regions[0].max_area == 0.5);
  CHECK(poly.regions[1].attribute == 20);
  CHECK(poly.regions[1].max_area == 20);  // four values: the fourth is both, as in Triangle
  CHECK(poly.regions[1].line == 27);
}

TEST_CASE("poly semantics: a loop with a hole point stays a hole", "[geometry]") {
  const PolyFile poly = read_poly_file(data("geometry/square_with_hole.poly"));
  CHECK(count_constraints(poly, true) == 0);
  // Only the region's maximum area is noted, with the spacing that sizes its subdomain.
  REQUIRE(poly.notes.size() == 1);
  CHECK_THAT(poly.notes[0], Contains("square_with_hole.poly:24: 1 region gives a maximum triangle area (the first: "
                                     "0.1); each such subdomain is sized so that its largest triangles have about "
                                     "that area (the first: spacing 0.3697)"));
  REQUIRE(poly.regions.size() == 1);
  CHECK(poly.regions[0].p == Vec2{3, 3});
  const Geometry g = read_geometry({data("geometry/square_with_hole.poly")}, {});
  REQUIRE(g.regions.size() == 1);
  CHECK(g.regions[0].max_area == 0.1);
}

TEST_CASE("poly semantics: Triangle's face.poly: open segments inside are constraints, dimples are points",
          "[geometry]") {
  const PolyFile poly = read_poly_file(data("triangle/face.poly"));
  CHECK(count_constraints(poly, false) == 4);   // the outline, the mouth and the two eyes
  REQUIRE(count_constraints(poly, true) == 2);  // the nostrils
  for (const RawCurve& c : poly.curves) CHECK(closed(c) != c.constraint);
  REQUIRE(poly.points.size() == 2);
  CHECK(poly.points[0].p == Vec2{-50, 0});
  CHECK(poly.points[0].line == 35);
  CHECK(any_note(poly, "2 isolated vertices (on no segment) inside the domain kept as mesh nodes"));
}

TEST_CASE("poly semantics: Triangle's la.poly: chains inside are constraints, six regions", "[geometry]") {
  const PolyFile poly = read_poly_file(data("triangle/la.poly"));
  CHECK(count_constraints(poly, true) > 0);
  CHECK(count_constraints(poly, false) > 0);
  REQUIRE(poly.regions.size() == 6);
  CHECK(poly.regions[5].attribute == 3);
  CHECK(poly.regions[5].max_area == 3);
  REQUIRE(poly.notes.size() == 1);
  CHECK_THAT(poly.notes[0], Contains("6 regions give a maximum triangle area"));
}

TEST_CASE("poly semantics: square_circle_hole.poly keeps its 691 isolated vertices", "[geometry]") {
  const Geometry g = read_geometry({data("triangle/square_circle_hole.poly")}, {});
  CHECK(g.embedded_points.size() == 691);
  CHECK(g.loops.size() == 2);
  REQUIRE(g.notes.size() == 1);
  CHECK_THAT(g.notes[0], Contains("691 isolated vertices"));
}

TEST_CASE("poly semantics: Triangle's box.poly meshes the convex hull minus the hole", "[geometry]") {
  const PolyFile poly = read_poly_file(data("triangle/box.poly"));
  CHECK(any_note(poly, "meshing the convex hull"));
  // The input side (marker 5), the hole's sides (markers 0 and 10), the hull's other three sides.
  REQUIRE(poly.curves.size() == 4);
  CHECK(poly.curves[0].points == std::vector<Vec2>{{0, 0}, {0, 3}});
  CHECK(poly.curves[3].name == "hull");
  CHECK(poly.curves[3].points.size() == 4);
  CHECK(count_constraints(poly, true) == 0);
  const Geometry g = read_geometry({data("triangle/box.poly")}, {});
  CHECK(g.area == 8.0);
  // geometry.hull = false: the only loop is a hole, nothing is left to mesh.
  CHECK_THROWS_WITH(read_poly_file(data("triangle/box.poly"), PolyHull::Off),
                    Contains("box.poly") && Contains("no area outside the holes") && Contains("geometry.hull"));
}

TEST_CASE("poly semantics: an open chain alone meshes the hull, the chain a constraint", "[geometry]") {
  const PolyFile poly = read_poly_file(data("geometry/open_chain_hull.poly"));
  REQUIRE(count_constraints(poly, true) == 1);
  CHECK(poly.curves.back().points == std::vector<Vec2>{{0, 0}, {1, 1.5}, {2, 2}});
  // The hull is split where the constraint meets it.
  CHECK(count_constraints(poly, false) == 2);
  CHECK(poly.curves[0].name == "hull0");
  CHECK(poly.points.empty());
  // geometry.hull = true on a file whose loops enclose area: the hull is added around them.
  const PolyFile nested = read_poly_file(data("geometry/nested_no_hole.poly"), PolyHull::On);
  CHECK(count_constraints(nested, false) == 1);  // the outer square is its own hull
  CHECK(count_constraints(nested, true) == 1);
}

TEST_CASE("poly semantics: bad regional attributes are input errors naming the line", "[geometry]") {
  CHECK_THROWS_AS(read_poly_file(data("geometry/region_bad_value.poly")), InputError);
  CHECK_THROWS_WITH(read_poly_file(data("geometry/region_bad_value.poly")),
                    Contains("region_bad_value.poly:11") && Contains("'x'"));
  CHECK_THROWS_WITH(read_poly_file(data("geometry/region_short.poly")),
                    Contains("region_short.poly:11") && Contains("should have 5 values, found 3"));
  CHECK_THROWS_WITH(read_poly_file(data("geometry/region_on_segment.poly")),
                    Contains("region_on_segment.poly:11") && Contains("(0.5, 0)") && Contains("on a segment"));
}

TEST_CASE("pdmesh mesh box.poly meshes the convex hull, and geometry.hull = false refuses it", "[cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("poly_hull");
  const std::string box = data("triangle/box.poly");
  const auto r = pdmesh_test::run_pdmesh("mesh '" + box + "' --out '" + (dir / "out").string() +
                                         "' --iterations 0 --formats msh --quiet");
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("pdmesh: note: ") && Contains("meshing the convex hull"));
  CHECK(fs::exists(dir / "out" / "mesh.msh"));
  const auto refused = pdmesh_test::run_pdmesh("mesh '" + box + "' --out '" + (dir / "refused").string() +
                                               "' --iterations 0 --set geometry.hull=false");
  CHECK(refused.status == 2);
  CHECK_THAT(refused.output, Contains("box.poly") && Contains("geometry.hull is false"));
  CHECK_FALSE(fs::exists(dir / "refused"));
}
