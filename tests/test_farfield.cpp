// The far field (geometry/farfield.hpp, --farfield, [farfield]): the curve's count, radius and
// closure, the smallest size, the airfoil meshed in its far field with the named group in the
// outputs, and the errors (exit 2, nothing written); a body with nested loops, constraints, points
// and regions is solid (left out, one note per kind) unless farfield.cavities = "mesh".
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "core/errors.hpp"
#include "geometry/farfield.hpp"
#include "geometry/geometry_files.hpp"
#include "io/msh_reader.hpp"
#include "mesh_measures.hpp"
#include "run_pdmesh.hpp"
#include "source_dir.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using pdmesh_test::fresh_path;
using pdmesh_test::run_pdmesh;

namespace {

Box unit_box() {
  Box b;
  b.add({0.0, 0.0});
  b.add({1.0, 0.5});
  return b;
}

std::string airfoil() { return pdmesh::test::source_dir() + "/cases/naca0012/airfoil.crv"; }

// A closed square curve [lo, hi]^2, counter-clockwise, named `name`.
RawCurve square(const std::string& name, double lo, double hi, bool constraint = false) {
  RawCurve c;
  c.name = name;
  c.file = name + ".crv";
  c.line = 1;
  c.points = {{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}, {lo, lo}};
  c.constraint = constraint;
  return c;
}

// The area of the far field's circle polygon at `size` around a body of largest extent `extent`.
double circle_polygon_area(double size, double extent) {
  const double n = 71.0, r = size * extent;
  return 0.5 * n * r * r * std::sin(2.0 * std::numbers::pi / n);
}

bool has_note(const Geometry& g, const std::string& part) {
  return std::any_of(g.notes.begin(), g.notes.end(), [&](const std::string& n) { return n.find(part) != n.npos; });
}

const Farfield kCircle20{FarfieldShape::Circle, 20.0, "test"};

}  // namespace

TEST_CASE("the circle's polygon has 71 sides within 0.1 % of its radius, closed, counter-clockwise") {
  REQUIRE(farfield_min_sides() == 71);
  const Farfield f{FarfieldShape::Circle, 20.0, "test"};
  const RawCurve c = farfield_curve(unit_box(), f, 0.01, 0.2);
  CHECK(c.name == "farfield");
  REQUIRE(c.points.size() == 72);
  CHECK(c.points.front().x == c.points.back().x);
  CHECK(c.points.front().y == c.points.back().y);
  const Vec2 o{0.5, 0.25};
  const double radius = 20.0;  // 20 x the largest extent, 1
  double area = 0.0, nearest = radius;
  for (std::size_t k = 0; k + 1 < c.points.size(); ++k) {
    const Vec2 a = c.points[k], b = c.points[k + 1];
    CHECK(std::fabs(dist(a, o) - radius) <= 1e-12 * radius);
    nearest = std::min(nearest, dist(Vec2{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)}, o));
    area += a.x * b.y - b.x * a.y;
  }
  CHECK(area > 0.0);
  // The polygon's farthest point inside the circle: the midpoints of its sides.
  CHECK(radius - nearest <= 1e-3 * radius);
  CHECK(radius - nearest > 0.9e-3 * radius);  // no more sides than the tolerance needs
}

TEST_CASE("the far field's sides shorten where the graded field is finer out there") {
  // Gradation 0.01 from a body of spacing 0.01: about 0.2 at the circle, below its 71-gon side 1.77.
  const Farfield f{FarfieldShape::Circle, 20.0, "test"};
  const RawCurve c = farfield_curve(unit_box(), f, 0.01, 0.01);
  const double side = dist(c.points[0], c.points[1]);
  CHECK(c.points.size() > 500);
  CHECK(side <= 0.01 + 0.01 * 20.0);
  const RawCurve off = farfield_curve(unit_box(), f, 0.01, 0.0);  // no gradation: the tolerance alone
  CHECK(off.points.size() == 72);
}

TEST_CASE("the box far field is a square of the half-width given, its sides split evenly") {
  const Farfield f{FarfieldShape::Box, 10.0, "test"};
  const RawCurve c = farfield_curve(unit_box(), f, 0.01, 0.2);
  double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
  for (const Vec2 p : c.points) {
    xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x), ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
  }
  CHECK(xmin == Approx(-9.5));
  CHECK(xmax == Approx(10.5));
  CHECK(ymin == Approx(-9.75));
  CHECK(ymax == Approx(10.25));
  CHECK((c.points.size() - 1) % 4 == 0);
}

TEST_CASE("a far field that does not clear the bounding box is an input error naming the size") {
  // Unit square: the circle's polygon must clear the corners, 0.5 sqrt(2) / cos(pi / 71) = 0.70780.
  Box square;
  square.add({0.0, 0.0});
  square.add({1.0, 1.0});
  const double least = 0.5 * std::sqrt(2.0) / std::cos(std::numbers::pi / 71.0);
  CHECK(farfield_min_size(square, {FarfieldShape::Circle, 1.0, ""}, 0.1) == Approx(least));
  CHECK_THROWS_WITH(farfield_curve(square, {FarfieldShape::Circle, 0.7, "[farfield]"}, 0.1, 0.2),
                    Catch::Contains("[farfield]") && Catch::Contains("size 0.7") && Catch::Contains("0.7078"));
  CHECK_NOTHROW(farfield_curve(square, {FarfieldShape::Circle, 0.71, "[farfield]"}, 0.1, 0.2));
  CHECK_THROWS_AS(farfield_curve(square, {FarfieldShape::Box, 0.5, "x"}, 0.1, 0.2), InputError);
  CHECK_NOTHROW(farfield_curve(square, {FarfieldShape::Box, 0.51, "x"}, 0.1, 0.2));
}

TEST_CASE("with_farfield makes the body a hole: two loops, the area of the circle less the body's") {
  const Geometry body = read_geometry({airfoil()}, {});
  const Geometry g = with_farfield(body, {FarfieldShape::Circle, 20.0, "test"}, 0.2, {});
  REQUIRE(g.curves.size() == body.curves.size() + 1);
  CHECK(g.curves.back().name == "farfield");
  CHECK(g.loops.size() == 2);
  const double n = 71.0, r = 20.0;
  const double polygon = 0.5 * n * r * r * std::sin(2.0 * std::numbers::pi / n);
  CHECK(g.area == Approx(polygon - body.area).epsilon(1e-9));
  // A body curve already named farfield would make two groups of one name.
  CHECK_THROWS_WITH(
      with_farfield(read_geometry({airfoil()}, {"farfield", "lower"}), {FarfieldShape::Circle, 20.0, "test"}, 0.2, {}),
      Catch::Contains("far field's name"));
}

TEST_CASE("pdmesh mesh airfoil.crv --farfield circle:20 meshes around the body, min angle >= 30, group farfield") {
  const auto out = fresh_path("farfield_airfoil");
  const auto r = run_pdmesh("mesh '" + airfoil() + "' --farfield circle:20 --formats msh --out '" + out.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("note: the geometry is one closed loop") == std::string::npos);
  MeshReadReport report;
  const Mesh m = read_msh(out / "mesh.msh", report);
  CHECK(std::find(m.curve_names.begin(), m.curve_names.end(), "farfield") != m.curve_names.end());
  CHECK(pdmesh_test::min_angle_deg(m) >= 30.0);
  // Nodes on the far field (radius 20 about the bounding box's centre) and none inside the airfoil.
  std::size_t on_circle = 0;
  for (const Vec2 p : m.points) {
    if (std::fabs(dist(p, Vec2{0.5, 0.0}) - 20.0) < 0.03) ++on_circle;
  }
  CHECK(on_circle >= 71);
  std::size_t in_airfoil = 0;
  for (const auto& t : m.triangles) {
    const Vec2 c{(m.points[t[0]].x + m.points[t[1]].x + m.points[t[2]].x) / 3.0,
                 (m.points[t[0]].y + m.points[t[1]].y + m.points[t[2]].y) / 3.0};
    if (c.x > 0.05 && c.x < 0.9 && std::fabs(c.y) < 0.01) ++in_airfoil;
  }
  CHECK(in_airfoil == 0);
  std::filesystem::remove_all(out);
}

TEST_CASE("a case file's [farfield] gives the same far field, bad values exit 2 and write nothing") {
  const auto dir = pdmesh_test::fresh_dir("farfield_case");
  const auto write_case = [&](const std::string& farfield) {
    std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"" << airfoil() << "\"]\n[simulation]\niterations = 0\n"
                                     << farfield;
  };
  const auto out = dir / "out";
  write_case("[farfield]\nshape = \"box\"\nsize = 10\n");
  auto r = run_pdmesh("mesh '" + dir.string() + "' --formats msh --out '" + out.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("2 loops") != std::string::npos);
  std::filesystem::remove_all(out);
  for (const auto& [text, named] : std::vector<std::pair<std::string, std::string>>{
           {"[farfield]\nshape = \"box\"\nsize = 0.4\n", "size 0.4"},
           {"[farfield]\nshape = \"oval\"\nsize = 10\n", "'oval'"},
           {"[farfield]\nshape = \"circle\"\n", "farfield.size is required"},
           {"[farfield]\nsize = -3\n", "farfield.size must be > 0, got -3"},
       }) {
    write_case(text);
    r = run_pdmesh("mesh '" + dir.string() + "' --out '" + out.string() + "'");
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find(named) != std::string::npos);
    CHECK(r.output.find("case.toml:") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
  }
  for (const char* option : {"circle:0.4", "circle", "disc:10", "circle:x"}) {
    r = run_pdmesh("mesh '" + airfoil() + "' --farfield " + option + " --out '" + out.string() + "'");
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find(std::string("--farfield ") + option) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("a closed body given alone meshes its inside and the message names --farfield") {
  const auto out = fresh_path("farfield_note");
  const std::string square = pdmesh::test::source_dir() + "/tests/data/geometry/unit_square.crv";
  const auto r = run_pdmesh("mesh '" + square + "' --iterations 0 --formats msh --out '" + out.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("its inside is meshed") != std::string::npos);
  CHECK(r.output.find("--farfield circle:20") != std::string::npos);
  std::filesystem::remove_all(out);
}

TEST_CASE("a far field with boundary layers: the core keeps the one far field, its group in the mesh") {
  // The core's case holds the case's curves, the far field among them: adding it again was an error.
  const auto out = fresh_path("farfield_layers");
  const auto r = run_pdmesh("mesh '" + airfoil() +
                            "' --farfield circle:20 --set 'boundary_layer={curves=[\"curve0\",\"curve1\"], "
                            "first_height=1e-3, thickness=0.01}' --iterations 0 --formats msh --out '" +
                            out.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  MeshReadReport report;
  const Mesh m = read_msh(out / "mesh.msh", report);
  CHECK(std::count(m.curve_names.begin(), m.curve_names.end(), "farfield") == 1);
  std::filesystem::remove_all(out);
}

TEST_CASE("a checkpoint of a far-field run resumes only with the same far field") {
  const auto out = fresh_path("farfield_resume");
  const std::string run = "mesh '" + airfoil() + "' --device host --formats msh -q --out '" + out.string() + "'";
  auto r = run_pdmesh(run + " --farfield circle:20 --stop-after 3");
  REQUIRE(r.status == 130);
  r = run_pdmesh(run + " --farfield circle:30 --resume '" + out.string() + "'");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("farfield is 'circle 20' there and 'circle 30'") != std::string::npos);
  std::filesystem::remove_all(out);
}

TEST_CASE("a far field around a body with a hole and its hole point: the body is solid, the hole left out") {
  RawGeometry raw;
  raw.curves = {square("outer", 0.0, 4.0), square("cavity", 1.0, 3.0)};
  raw.holes = {{{2.0, 2.0}, "body.poly", 9}};
  const Geometry body = build_geometry(raw);
  REQUIRE(body.hole_points.size() == 1);
  const Geometry g = with_farfield(body, kCircle20, 0.2, {});
  REQUIRE(g.loops.size() == 2);
  REQUIRE(g.curves.size() == 2);
  CHECK(g.curves[0].name == "outer");
  CHECK(g.curves[1].name == "farfield");
  CHECK(g.hole_points.empty());
  CHECK(g.area == Approx(circle_polygon_area(20.0, 4.0) - 16.0).epsilon(1e-12));
  REQUIRE(g.notes.size() == 2);
  CHECK(has_note(g, "leaves out 1 loop nested inside the body"));
  CHECK(has_note(g, "curve 'cavity' (cavity.crv:1)"));
  CHECK(has_note(g, "leaves out 1 hole point inside the body"));
  CHECK(has_note(g, "the first: (2, 2) (body.poly:9)"));
}

TEST_CASE("a far field around a body with an embedded constraint, point and region: they are left out") {
  RawGeometry raw;
  raw.curves = {square("outer", 0.0, 4.0)};
  RawCurve line;
  line.name = "web";
  line.file = "body.crv";
  line.line = 12;
  line.points = {{1.0, 1.0}, {3.0, 1.0}};
  line.constraint = true;
  raw.curves.push_back(line);
  raw.curves.push_back(square("inner", 2.0, 3.0, true));
  raw.points = {{{2.5, 3.5}, "body.poly", 20}, {{0.5, 3.0}, "body.poly", 21}};
  Geometry body = build_geometry(raw);
  REQUIRE(body.embedded_points.size() == 2);
  body.regions = {{{0.5, 0.5}, 3.0, -1.0, "body.poly", 30, ""}, {{50.0, 50.0}, 4.0, -1.0, "body.poly", 31, ""}};
  const Geometry g = with_farfield(body, kCircle20, 0.2, {});
  REQUIRE(g.curves.size() == 2);
  CHECK(std::none_of(g.curves.begin(), g.curves.end(), [](const Curve& c) { return c.constraint; }));
  CHECK(g.embedded_points.empty());
  // The region point outside the body lies in the flow domain: kept.
  REQUIRE(g.regions.size() == 1);
  CHECK(g.regions[0].attribute == 4.0);
  CHECK(g.loops.size() == 2);
  REQUIRE(g.notes.size() == 3);
  CHECK(has_note(g, "leaves out 2 embedded constraint curves inside the body, the first: curve 'web' (body.crv:12)"));
  CHECK(has_note(g, "leaves out 2 embedded points inside the body, the first: (2.5, 3.5) (body.poly:20)"));
  CHECK(has_note(g, "leaves out 1 region point inside the body, the first: (0.5, 0.5) (body.poly:30)"));
}

TEST_CASE("a far field around a body whose cavity holds an island: the island is inside the body, solid too") {
  const Geometry body =
      build_geometry({square("outer", 0.0, 6.0), square("cavity", 1.0, 5.0), square("island", 2.0, 4.0)});
  REQUIRE(body.loops.size() == 3);
  const Geometry g = with_farfield(body, kCircle20, 0.2, {});
  REQUIRE(g.loops.size() == 2);
  CHECK(g.curves[0].name == "outer");
  CHECK(g.area == Approx(circle_polygon_area(20.0, 6.0) - 36.0).epsilon(1e-12));
  REQUIRE(g.notes.size() == 1);
  CHECK(has_note(g, "leaves out 2 loops nested inside the body"));
  CHECK(has_note(g, "the first: curve 'cavity'"));
}

TEST_CASE("farfield.cavities = mesh keeps every loop: the even-odd rule and its checks as given") {
  const Farfield mesh{FarfieldShape::Circle, 20.0, "test", FarfieldCavities::Mesh};
  const Geometry nested =
      build_geometry({square("outer", 0.0, 6.0), square("cavity", 1.0, 5.0), square("island", 2.0, 4.0)});
  const Geometry g = with_farfield(nested, mesh, 0.2, {});
  CHECK(g.loops.size() == 4);
  CHECK(g.notes.empty());
  CHECK(g.area == Approx(circle_polygon_area(20.0, 6.0) - 36.0 + 16.0 - 4.0).epsilon(1e-12));
  RawGeometry raw;
  raw.curves = {square("outer", 0.0, 4.0), square("cavity", 1.0, 3.0)};
  raw.holes = {{{2.0, 2.0}, "body.poly", 9}};
  // The error names where the hole point was read, not the far field.
  CHECK_THROWS_WITH(with_farfield(build_geometry(raw), mesh, 0.2, {}),
                    Catch::StartsWith("body.poly:9: hole point (2, 2) lies inside the domain"));
  RawGeometry with_point;
  with_point.curves = {square("outer", 0.0, 4.0), square("cavity", 1.0, 3.0)};
  with_point.points = {{{0.5, 0.5}, "body.poly", 14}};
  CHECK_THROWS_WITH(with_farfield(build_geometry(with_point), mesh, 0.2, {}),
                    Catch::StartsWith("body.poly:14: point (0.5, 0.5) lies outside the domain"));
}

TEST_CASE("a far field around bodies without nested loops: both modes give the geometry of the plain rule") {
  const Geometry body = build_geometry({square("left", 0.0, 1.0), square("right", 2.0, 3.0)});
  const Geometry solid = with_farfield(body, kCircle20, 0.2, {});
  const Geometry mesh = with_farfield(body, {FarfieldShape::Circle, 20.0, "test", FarfieldCavities::Mesh}, 0.2, {});
  CHECK(solid.notes.empty());
  REQUIRE(solid.curves.size() == 3);
  REQUIRE(mesh.curves.size() == 3);
  for (std::size_t c = 0; c < 3; ++c) {
    CHECK(solid.curves[c].name == mesh.curves[c].name);
    CHECK(solid.curves[c].points == mesh.curves[c].points);
    if (c < 2) CHECK(solid.curves[c].points == body.curves[c].points);
  }
  CHECK(solid.loops.size() == 3);
  CHECK(solid.area == mesh.area);
}

TEST_CASE("pdmesh mesh of a .poly with a hole and a hole point and a far field: meshed around, the note said") {
  const auto dir = pdmesh_test::fresh_dir("farfield_holes");
  const auto out = dir / "out";
  const std::string poly = pdmesh::test::source_dir() + "/cases/user_corpus/A/A.poly";
  const std::string run = "mesh '" + poly + "' --iterations 0 --formats msh -q --out '" + out.string() + "'";
  auto r = run_pdmesh(run + " --farfield circle:5");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("note: --farfield circle:5: the far field leaves out 1 loop nested") != std::string::npos);
  CHECK(r.output.find("leaves out 1 hole point inside the body") != std::string::npos);
  std::filesystem::remove_all(out);
  r = run_pdmesh(run + " --farfield circle:5 --set farfield.cavities=mesh");
  CHECK(r.status == 2);
  CHECK(r.output.find("error: " + poly + ":62: hole point (0.47, -0.5) lies inside the domain, not in a hole") !=
        std::string::npos);
  r = run_pdmesh(run + " --farfield circle:5 --set farfield.cavities=hollow");
  CHECK(r.status == 2);
  CHECK(r.output.find("farfield.cavities must be one of solid, mesh, got 'hollow'") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}
