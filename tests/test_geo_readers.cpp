// The readers of geometry as users bring it (issue 39): Selig and Lednicer airfoil files, GeoJSON,
// shapefiles, and the equirectangular projection of lon/lat data; their RawGeometry and their errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

#include "core/errors.hpp"
#include "error_message.hpp"
#include "geometry/airfoil_reader.hpp"
#include "geometry/geojson_reader.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/projection.hpp"
#include "geometry/shapefile_reader.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;
using pdmesh_test::error_message;

namespace {

std::string data(const std::string& name) { return std::string(PDMESH_SOURCE_DIR "/tests/data/geometry/") + name; }

std::string write(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  const auto p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

const RawCurve& named(const RawGeometry& g, const std::string& name) {
  for (const RawCurve& c : g.curves)
    if (c.name == name) return c;
  FAIL("no curve named " << name);
  return g.curves.front();
}

}  // namespace

TEST_CASE("a count-format .dat file is read as before, a name line makes it an airfoil", "[geometry][airfoil]") {
  const auto dir = pdmesh_test::fresh_dir("airfoil_detect");
  const std::string count = write(dir, "square.dat", "# square\n5\n0 0\n1 0\n1 1\n0 1\n0 0\n");
  const RawGeometry raw = read_geometry_files({count});
  REQUIRE(raw.curves.size() == 1);
  CHECK(raw.curves[0].name.empty());  // default names, as for every count-format file
  CHECK(raw.curves[0].points.size() == 5);
  // The count format's own errors stay: a lone number is a count.
  CHECK_THROWS_WITH(read_geometry_files({write(dir, "frac.dat", "2.5\n0 0\n1 1\n")}),
                    Contains("frac.dat:1") && Contains("not a non-negative integer"));
}

TEST_CASE("Selig files: s1223 (sharp trailing edge) splits into upper and lower at the leading edge",
          "[geometry][airfoil]") {
  const RawGeometry raw = read_geometry_files({data("airfoils/s1223.dat")});
  REQUIRE(raw.curves.size() == 2);
  const RawCurve& upper = named(raw, "upper");
  const RawCurve& lower = named(raw, "lower");
  // 300 point lines, the last repeating the first (the sharp trailing edge): 299 distinct points,
  // the leading edge in both curves, the trailing edge closing the loop.
  CHECK(upper.points.size() + lower.points.size() == 299 + 2);
  CHECK(upper.points.front() == Vec2{1.0, 0.0});
  CHECK(lower.points.back() == Vec2{1.0, 0.0});
  CHECK(upper.points.back() == lower.points.front());
  CHECK(upper.points.back().x == Approx(0.0).margin(1e-4));  // the leading edge
  CHECK(upper.lines.front() == 2);                           // the name line is line 1
  CHECK(upper.file == data("airfoils/s1223.dat"));
  const Geometry g = read_geometry({data("airfoils/s1223.dat")}, {});
  REQUIRE(g.loops.size() == 1);
  CHECK(g.curves.size() == 2);
  CHECK(g.area > 0.05);
  CHECK(g.area < 0.2);
}

TEST_CASE("Selig files: naca2412 (blunt trailing edge) gets a te curve", "[geometry][airfoil]") {
  const RawGeometry raw = read_geometry_files({data("airfoils/naca2412.dat")});
  REQUIRE(raw.curves.size() == 3);
  CHECK(raw.curves[0].name == "upper");
  CHECK(raw.curves[1].name == "lower");
  CHECK(raw.curves[2].name == "te");
  CHECK(raw.curves[2].points == std::vector<Vec2>{{1.0, -0.0012573}, {1.0, 0.0012573}});
  CHECK(named(raw, "upper").points.front() == Vec2{1.0, 0.0012573});
  CHECK(named(raw, "upper").points.back() == Vec2{0.0, 0.0});
  const Geometry g = read_geometry({data("airfoils/naca2412.dat")}, {});
  CHECK(g.loops.size() == 1);
}

TEST_CASE("Lednicer files give the same curves as the Selig file they were written from", "[geometry][airfoil]") {
  const RawGeometry selig = read_geometry_files({data("airfoils/naca2412.dat")});
  const RawGeometry lednicer = read_geometry_files({data("airfoils/naca2412_lednicer.dat")});
  REQUIRE(lednicer.curves.size() == selig.curves.size());
  for (std::size_t c = 0; c < selig.curves.size(); ++c) {
    CHECK(lednicer.curves[c].name == selig.curves[c].name);
    CHECK(lednicer.curves[c].points == selig.curves[c].points);
  }
  // The upper surface's first point in the file is its leading edge, on line 4 (after the name,
  // the counts and a blank line).
  CHECK(named(lednicer, "upper").lines.back() == 4);
}

TEST_CASE("airfoil files: a file going over the lower surface first still names upper and lower by side",
          "[geometry][airfoil]") {
  const auto dir = pdmesh_test::fresh_dir("airfoil_clockwise");
  // Trailing edge, lower surface, leading edge, upper surface: clockwise.
  const std::string f = write(dir, "cw.dat", "cw\n1 0\n0.5 -0.05\n0 0\n0.5 0.06\n1 0\n");
  const RawGeometry raw = read_geometry_files({f});
  REQUIRE(raw.curves.size() == 2);
  CHECK(raw.curves[0].name == "upper");
  CHECK(raw.curves[0].points.size() == 3);
  CHECK(raw.curves[0].points[1] == Vec2{0.5, 0.06});
}

TEST_CASE("airfoil files: repeated consecutive points are dropped, a file without a name line is Selig",
          "[geometry][airfoil]") {
  const auto dir = pdmesh_test::fresh_dir("airfoil_repeats");
  const std::string f = write(dir, "rep.dat", "1 0.01\n0.5 0.05\n0.5 0.05\n0 0\n0 0\n0.5 -0.04\n1 -0.01\n");
  const std::vector<detail::TokenLine> lines = detail::read_token_lines(f);
  CHECK_FALSE(is_count_format(lines));
  const AirfoilFile a = read_airfoil_lines(f, lines);
  REQUIRE(a.notes.size() == 1);
  CHECK_THAT(a.notes[0], Contains("dropped 2 repeated consecutive points") && Contains("lines 3, 5"));
  REQUIRE(a.curves.size() == 3);
  CHECK(a.curves[0].points.size() == 3);  // (1, 0.01), (0.5, 0.05), (0, 0)
  CHECK(a.curves[1].points.size() == 3);
  CHECK(a.curves[2].name == "te");
  CHECK(build_geometry(a.curves).loops.size() == 1);
}

TEST_CASE("two airfoil files get their file stems as name prefixes", "[geometry][airfoil]") {
  const auto dir = pdmesh_test::fresh_dir("airfoil_two");
  const std::string moved = write(dir, "e387.dat", "");
  {
    // e387 moved 2 chords up, so the loops do not cross.
    std::ifstream in(data("airfoils/e387.dat"));
    std::ofstream out(moved);
    std::string line;
    std::getline(in, line);
    out << line << "\n";
    double x = 0, y = 0;
    while (in >> x >> y) out << x << " " << y + 2 << "\n";
  }
  const Geometry g = read_geometry({data("airfoils/naca2412.dat"), moved}, {});
  std::vector<std::string> names;
  for (const Curve& c : g.curves) names.push_back(c.name);
  CHECK(names ==
        std::vector<std::string>{"naca2412_upper", "naca2412_lower", "naca2412_te", "e387_upper", "e387_lower"});
  CHECK(g.loops.size() == 2);
}

TEST_CASE("airfoil file errors name the file, line and value", "[geometry][airfoil]") {
  const auto dir = pdmesh_test::fresh_dir("airfoil_errors");
  CHECK_THROWS_WITH(read_geometry_files({write(dir, "three.dat", "foil\n1 0\n0.5 0.1 7\n")}),
                    Contains("three.dat:3") && Contains("expected an airfoil point 'x y'") && Contains("0.5 0.1 7"));
  CHECK_THROWS_WITH(read_geometry_files({write(dir, "word.dat", "foil\n1 0\n0.5 abc\n0 0\n")}),
                    Contains("word.dat:3") && Contains("'abc' is not a number"));
  CHECK_THROWS_WITH(read_geometry_files({write(dir, "two.dat", "foil\n1 0\n0 0\n1 0\n")}),
                    Contains("two.dat:2") && Contains("at least 3 distinct points, found 2"));
  CHECK_THROWS_AS(read_geometry_files({write(dir, "name.dat", "just a name\n")}), InputError);
}

TEST_CASE("GeoJSON: polygons with holes, names made plain and distinct", "[geometry][geojson]") {
  const RawGeometry raw = read_geojson_file(data("gis/lake.geojson"));
  REQUIRE(raw.curves.size() == 3);
  CHECK(raw.curves[0].name == "lake_shore");
  CHECK(raw.curves[1].name == "lake_shore_hole1");
  CHECK(raw.curves[2].name == "islet");
  CHECK(raw.curves[0].points.size() == 5);  // closed: the first point again at the end
  CHECK(raw.curves[0].points.front() == raw.curves[0].points.back());
  CHECK(raw.curves[0].line == 4);  // the feature's '{'
  CHECK(raw.curves[2].line == 15);
  CHECK_FALSE(raw.curves[0].constraint);
  const Geometry g = read_geometry({data("gis/lake.geojson")}, {});
  CHECK(g.loops.size() == 3);
  CHECK(g.area == Approx(100.0 - 4.0 + 0.5));  // even-odd: the islet lies in the hole
}

TEST_CASE("GeoJSON: every geometry type, collections, repeats and null geometries", "[geometry][geojson]") {
  const RawGeometry raw = read_geojson_file(data("gis/mixed.geojson"));
  std::vector<std::string> names;
  std::vector<bool> constraint;
  for (const RawCurve& c : raw.curves) {
    names.push_back(c.name);
    constraint.push_back(c.constraint);
  }
  // The MultiPolygon's parts are land_1, land_2; the second 'land' feature's polygon stays 'land' (a
  // name occurring once); the lines of a MultiLineString without a name stay unnamed.
  CHECK(names == std::vector<std::string>{"land_1", "land_2", "land_2_hole1", "road", "land", "", ""});
  CHECK(constraint == std::vector<bool>{false, false, false, true, false, true, true});
  CHECK(raw.curves[3].points == std::vector<Vec2>{{1, 1}, {2, 2}, {3, 1}});  // z ignored
  REQUIRE(raw.points.size() == 3);
  CHECK(raw.points[0].p == Vec2{1, 3});
  CHECK(raw.points[2].p == Vec2{3, 3});
  CHECK(raw.points[0].line == 12);
  // Built: the lines are constraints of the geometry, the points embedded points.
  const Geometry g = read_geometry({data("gis/mixed.geojson")}, {});
  int constraints = 0;
  for (const Curve& c : g.curves) constraints += c.constraint;
  CHECK(constraints >= 3);  // road and the two unnamed lines (split where they meet)
  bool road = false;
  for (const Curve& c : g.curves) road |= c.name == "road" && c.constraint;
  CHECK(road);
  CHECK(g.embedded_points.size() == 3);
}

TEST_CASE("GeoJSON: embedded points are kept by read_geometry", "[geometry][geojson]") {
  const auto dir = pdmesh_test::fresh_dir("geojson_points");
  const std::string f = write(dir, "wells.geojson",
                              "{\"type\": \"GeometryCollection\", \"geometries\": [\n"
                              "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [4, 0], [4, 4], [0, 0]]]},\n"
                              "{\"type\": \"Point\", \"coordinates\": [3, 1]}]}\n");
  const RawGeometry raw = read_geometry_files({f});
  CHECK(raw.curves.size() == 1);
  REQUIRE(raw.points.size() == 1);
  CHECK(raw.points[0].p == Vec2{3, 1});
  const Geometry g = read_geometry({f}, {});
  REQUIRE(g.embedded_points.size() == 1);
  CHECK(g.embedded_points[0].p == Vec2{3, 1});
}

TEST_CASE("GeoJSON: a bare geometry in a .json file", "[geometry][geojson]") {
  const Geometry g = read_geometry({data("gis/square.json")}, {});
  CHECK(g.area == 1.0);
  CHECK(g.curves.size() == 1);
}

TEST_CASE("GeoJSON errors: malformed JSON with line and column, unknown types, short rings, points only",
          "[geometry][geojson]") {
  const std::string f = "x.geojson";
  CHECK_THROWS_WITH(read_geojson_text(f, "{\"type\": \"Polygon\",\n \"coordinates\": [[0, 0],\n}"),
                    Contains("x.geojson:3:1: malformed JSON") && Contains("syntax error"));
  CHECK_THROWS_WITH(read_geojson_text(f, "{\"type\": \"Polygon\" \"coordinates\": []}"),
                    Contains("x.geojson:1:32: malformed JSON") && Contains("expected '}'"));
  CHECK_THROWS_WITH(read_geojson_text(f,
                                      "{\"type\": \"FeatureCollection\", \"features\": [\n"
                                      "{\"type\": \"Feature\", \"properties\": {\"name\": \"c\"},\n"
                                      " \"geometry\": {\"type\": \"Circle\", \"coordinates\": [0, 0]}}]}"),
                    Contains("x.geojson:3: feature 0 ('c'): unknown GeoJSON geometry type 'Circle'"));
  CHECK_THROWS_WITH(read_geojson_text(f, "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [1, 0], [0, 0]]]}"),
                    Contains("x.geojson:1: the geometry: ring 0 has 2 distinct points") && Contains("at least 3"));
  CHECK_THROWS_WITH(
      read_geojson_text(f, "{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [1, \"a\"]]]}"),
      Contains("x.geojson:1") && Contains("a position must be an array of 2 or 3 numbers") && Contains("[1,\"a\"]"));
  CHECK_THROWS_WITH(read_geojson_text(f, "{\"type\": \"MultiPoint\", \"coordinates\": [[0, 0], [1, 1]]}"),
                    Contains("x.geojson: the file holds 2 points and no polygon or line"));
  CHECK_THROWS_WITH(read_geojson_text(f, "[1, 2]"), Contains("x.geojson:1: the top level is array"));
  CHECK_THROWS_WITH(read_geojson_text(f, "{\"type\": \"Feature\", \"properties\": null}"),
                    Contains("x.geojson:1: the object has no 'geometry' member"));
}

TEST_CASE("shapefiles: polygons with holes by ring orientation, names from the .dbf", "[geometry][shapefile]") {
  const RawGeometry raw = read_shapefile(data("gis/lake.shp"));
  REQUIRE(raw.curves.size() == 3);
  CHECK(raw.curves[0].name == "lake_shore");
  CHECK(raw.curves[1].name == "lake_shore_hole1");
  CHECK(raw.curves[2].name == "islet");
  CHECK(raw.curves[2].line == 2);  // the record number
  CHECK(raw.curves[0].points.size() == 5);
  const Geometry g = read_geometry({data("gis/lake.shp")}, {});
  CHECK(g.area == Approx(100.0 - 4.0 + 0.5));
  // The same geometry as the GeoJSON file (rings run the other way there).
  const Geometry h = read_geometry({data("gis/lake.geojson")}, {});
  CHECK(g.area == h.area);
}

TEST_CASE("shapefiles: PolygonZ, PolyLine constraints, and a file of points only", "[geometry][shapefile]") {
  const RawGeometry z = read_shapefile(data("gis/lake_z.shp"));
  REQUIRE(z.curves.size() == 1);
  CHECK(z.curves[0].name.empty());  // the .dbf has no name field
  CHECK(z.curves[0].points[2] == Vec2{10, 10});
  const RawGeometry roads = read_shapefile(data("gis/roads.shp"));
  REQUIRE(roads.curves.size() == 3);
  CHECK(roads.curves[0].name == "road_1");
  CHECK(roads.curves[1].name == "road_2");
  CHECK(roads.curves[2].name == "levee");
  for (const RawCurve& c : roads.curves) CHECK(c.constraint);
  CHECK(roads.curves[1].points == std::vector<Vec2>{{3, 3}, {8, 2}});
  CHECK_THROWS_WITH(read_shapefile(data("gis/wells.shp")),
                    Contains("wells.shp: the file holds 2 points and no polygon or line: nothing bounds a domain"));
  CHECK_THROWS_WITH(read_shapefile(data("gis/no_such.shp")), Contains("no_such.shp") && Contains("cannot read"));
  const auto dir = pdmesh_test::fresh_dir("shapefile_no_shx");
  std::filesystem::copy_file(data("gis/lake.shp"), dir / "lake.shp");
  const std::string msg = error_message<InputError>([&] { read_shapefile((dir / "lake.shp").string()); });
  CHECK_THAT(msg, Contains("lake.shp: cannot read the shapefile: Unable to open") &&
                      Contains("(a shapefile needs its .shx index beside it)"));
  CHECK_THAT(msg, !Contains("SHAPE_RESTORE_SHX"));  // GDAL's option, not pdmesh's
}

TEST_CASE("equirectangular projection: metres about the centre, and back", "[geometry][projection]") {
  RawGeometry raw = read_geojson_file(data("gis/lonlat_square.geojson"));
  const Equirectangular p = project_lonlat(raw);
  CHECK(p.lon0 == Approx(10.05));
  CHECK(p.lat0 == Approx(50.05));
  const double R = Equirectangular::kEarthRadius;
  const double deg = M_PI / 180.0;
  const Vec2 corner = raw.curves[0].points[0];  // was (10, 50)
  CHECK(corner.x == Approx(-R * std::cos(50.05 * deg) * 0.05 * deg));
  CHECK(corner.y == Approx(-R * 0.05 * deg));
  const Vec2 back = p.inverse(corner);
  CHECK(back.x == Approx(10.0).margin(1e-12));
  CHECK(back.y == Approx(50.0).margin(1e-12));
  // Through read_geometry: the box is about 7.2 km by 11.1 km.
  Equirectangular used;
  const Geometry g =
      read_geometry({data("gis/lonlat_square.geojson")}, {}, {}, {ProjectionKind::Equirectangular, &used, {}, {}});
  CHECK(used.lat0 == p.lat0);
  CHECK(g.extents.hi.x - g.extents.lo.x == Approx(R * std::cos(50.05 * deg) * 0.1 * deg));
}

TEST_CASE("equirectangular projection of data that is not lon/lat is refused naming the file and value",
          "[geometry][projection]") {
  const auto dir = pdmesh_test::fresh_dir("projection_errors");
  const std::string utm = write(dir, "utm.geojson",
                                "{\"type\": \"Polygon\",\n \"coordinates\": [[[500000, 5500000], [501000, 5500000], "
                                "[501000, 5501000], [500000, 5500000]]]}");
  CHECK_NOTHROW(read_geometry({utm}, {}));  // projected data is taken as given
  CHECK_THROWS_WITH(read_geometry({utm}, {}, {}, {ProjectionKind::Equirectangular, nullptr, {}, {}}),
                    Contains("utm.geojson:1: point (500000, 5500000) is not longitude/latitude"));
  const std::string msg = error_message<InputError>([] {
    RawGeometry raw = read_geometry_files({data("airfoils/naca2412.dat")});
    raw.curves[0].points[3] = {10.0, 95.0};
    project_lonlat(raw);
  });
  CHECK_THAT(msg, Contains("naca2412.dat:5: point (10, 95) is not longitude/latitude"));
}
