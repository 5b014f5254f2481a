// Healing at the mesh's resolution (geometry/heal.hpp) on the synthetic defects of tests/data/heal
// (tools/cases/make_heal_defects.py), clean inputs that it must leave alone, and whole runs of the
// command: min angle after default healing, the report on stderr and in quality.json, healing.png,
// and geometry.heal = false meshing the input exactly. Also the short-arc spacing rule
// (spacing/short_arcs.hpp) on a blunt trailing edge and a rectangle with one tiny edge.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "app/config/case_file.hpp"
#include "core/errors.hpp"
#include "geometry/curve_reader.hpp"
#include "geometry/geometry.hpp"
#include "geometry/heal.hpp"
#include "geometry/heal_report.hpp"
#include "json_check.hpp"
#include "run_pdmesh.hpp"
#include "spacing/short_arcs.hpp"
#include "spacing/spacing_field.hpp"
#include "geometry/geometry_tree.hpp"
#include "temp_files.hpp"

using namespace pdmesh;

namespace {

std::string data(const std::string& name) { return std::string(PDMESH_SOURCE_DIR) + "/tests/data/heal/" + name; }

double shortest_segment(const std::vector<RawCurve>& curves) {
  double s = INFINITY;
  for (const RawCurve& c : curves)
    for (std::size_t k = 0; k + 1 < c.points.size(); ++k) s = std::min(s, dist(c.points[k], c.points[k + 1]));
  return s;
}

// quality.json's "min" of "included_angle".
double min_angle(const std::string& json) {
  const std::string key = "\"included_angle\": {\"min\": ";
  const std::size_t at = json.find(key);
  REQUIRE(at != std::string::npos);
  return std::stod(json.substr(at + key.size()));
}

}  // namespace

TEST_CASE("merged polygons: the 0.3-2.6 m steps merge into their neighbours") {
  std::vector<RawCurve> curves = read_curve_file(data("merged.crv"));
  REQUIRE(shortest_segment(curves) < 0.5);
  const HealResult r = heal_curves(curves);
  CHECK(r.count(HealKind::Merge) >= 4);
  CHECK(r.count(HealKind::Merge) == static_cast<int>(r.changes.size()));
  CHECK(r.worst(HealKind::Merge)->size < 2.0);
  CHECK(shortest_segment(curves) > 250.0);
  CHECK_NOTHROW(build_geometry(curves));
}

TEST_CASE("an inlet 100 m wide in a coast sampled at 1 km is closed at its mouth") {
  std::vector<RawCurve> curves = read_curve_file(data("inlet.crv"));
  const double before = build_geometry(curves).area;
  const HealResult r = heal_curves(curves);
  REQUIRE(r.count(HealKind::InletClosed) == 1);
  // Then the mouth's two corners, 100 m apart, merge.
  CHECK(r.count(HealKind::Merge) == 1);
  CHECK(r.changes.size() == 2);
  const HealChange& c = *r.worst(HealKind::InletClosed);
  CHECK(c.size == Approx(100.0));
  CHECK(c.at.x == Approx(10050.0));
  CHECK(c.at.y == Approx(0.0).margin(1e-9));
  CHECK(c.added.size() == 2);
  // The domain loses the inlet, 100 m x 3 km (the merge moves no area: its points are collinear).
  CHECK(before - build_geometry(curves).area == Approx(100.0 * 3000.0));
}

TEST_CASE("a narrow intrusion into the domain is opened") {
  std::vector<RawCurve> curves = read_curve_file(data("inlet.crv"));
  // The coast inside a larger box: its interior becomes a hole, its inlet a tongue of land 100 m
  // wide reaching into the water, which healing removes (the water gains it).
  RawCurve outer;
  outer.points = {{-5000, -10000}, {25000, -10000}, {25000, 15000}, {-5000, 15000}, {-5000, -10000}};
  outer.file = "memory";
  curves.insert(curves.begin(), outer);
  const double before = build_geometry(curves).area;
  const HealResult r = heal_curves(curves);
  REQUIRE(r.count(HealKind::InletOpened) == 1);
  CHECK(r.count(HealKind::InletClosed) == 0);
  // The water gains the tongue.
  CHECK(build_geometry(curves).area - before == Approx(100.0 * 3000.0));
}

TEST_CASE("a one-vertex spike goes, its 10 m base merges") {
  std::vector<RawCurve> curves = read_curve_file(data("spike.crv"));
  const HealResult r = heal_curves(curves);
  REQUIRE(r.count(HealKind::Spike) == 1);
  CHECK(r.worst(HealKind::Spike)->at.y == Approx(700.0));
  CHECK(r.count(HealKind::Merge) == 1);
  for (const Vec2 p : curves.front().points) CHECK(p.y <= 10000.0);
  for (const Vec2 p : curves.front().points) CHECK(!(p.y > 1.0 && p.y < 1000.0));
}

TEST_CASE("a 30 m island in a km-scale sea is dropped") {
  std::vector<RawCurve> curves = read_curve_file(data("island.crv"));
  REQUIRE(curves.size() == 2);
  const HealResult r = heal_curves(curves);
  REQUIRE(r.count(HealKind::Island) == 1);
  CHECK(r.changes.front().size == Approx(900.0));
  CHECK(curves.size() == 1);
}

TEST_CASE("a loop that holds a stated hole point is kept, however small") {
  std::vector<RawCurve> curves = read_curve_file(data("island.crv"));
  REQUIRE(curves.size() == 2);
  Vec2 centre{0.0, 0.0};
  for (std::size_t k = 0; k + 1 < curves[1].points.size(); ++k) centre = centre + curves[1].points[k];
  centre = (1.0 / static_cast<double>(curves[1].points.size() - 1)) * centre;
  HealOptions options;
  options.holes = {{-1.0e6, -1.0e6}, centre};  // one outside every loop, one in the island
  const std::vector<RawCurve> before = curves;
  const HealResult r = heal_curves(curves, options);
  CHECK(r.count(HealKind::Island) == 0);
  REQUIRE(curves.size() == 2);
  CHECK(curves[1].points == before[1].points);
}

// face.poly's eyes are triangles with a hole point each; at twice its scale they are below the
// island rule's area, and dropping one left its hole point inside the domain (an input error).
TEST_CASE("pdmesh mesh on a .poly with small holes at spacing.scale = 2: the holes stay, a valid mesh") {
  const auto dir = pdmesh_test::fresh_dir("heal_poly_holes");
  const auto r =
      pdmesh_test::run_pdmesh("mesh '" + std::string(PDMESH_SOURCE_DIR) +
                              "/cases/user_corpus/face/case.toml' --set spacing.scale=2 --out '" + dir.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("islands dropped") == std::string::npos);
  CHECK(min_angle(pdmesh_test::slurp(dir / "quality.json")) >= 30.0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("healing leaves clean inputs alone: every curve file of cases/, a blunt trailing edge, a tiny edge") {
  std::vector<std::string> files = {data("blunt_te.crv"), data("tiny_edge.crv")};
  for (const auto& e : std::filesystem::recursive_directory_iterator(std::string(PDMESH_SOURCE_DIR) + "/cases"))
    if (e.path().extension() == ".crv") files.push_back(e.path().string());
  REQUIRE(files.size() > 10);
  for (const std::string& file : files) {
    INFO(file);
    std::vector<RawCurve> curves = read_curve_file(file);
    const std::vector<RawCurve> before = curves;
    const HealResult r = heal_curves(curves);
    CHECK(r.changes.empty());
    REQUIRE(curves.size() == before.size());
    for (std::size_t c = 0; c < curves.size(); ++c) CHECK(curves[c].points == before[c].points);
  }
}

TEST_CASE("a coarser mesh (spacing.scale) merges the same steps and leaves a curve's regular sampling alone") {
  HealOptions coarse;
  coarse.scale = 4.0;
  {
    std::vector<RawCurve> at_one = read_curve_file(data("merged.crv"));
    std::vector<RawCurve> at_four = at_one;
    const HealResult one = heal_curves(at_one);
    const HealResult four = heal_curves(at_four, coarse);
    REQUIRE(one.count(HealKind::Merge) >= 4);
    CHECK(four.count(HealKind::Merge) == one.count(HealKind::Merge));
    REQUIRE(at_four.size() == at_one.size());
    for (std::size_t c = 0; c < at_one.size(); ++c) CHECK(at_four[c].points == at_one[c].points);
  }
  // At 4x the spacing a quarter of the (scaled) spacing is about a whole segment of a regularly sampled
  // curve: merges judged by it took about half of the segments for jogs, round after round.
  for (const std::string& file :
       {data("blunt_te.crv"), data("tiny_edge.crv"), std::string(PDMESH_SOURCE_DIR) + "/cases/30p30n/airfoil.crv"}) {
    INFO(file);
    std::vector<RawCurve> curves = read_curve_file(file);
    const HealResult r = heal_curves(curves, coarse);
    CHECK(r.count(HealKind::Merge) == 0);
  }
}

// A sharp-trailing-edge airfoil of 61 points (3.9 degree wedge) meshed 4x coarser than its defaults:
// the same merges as at its own scale (the points next to the trailing edge), so the wedge's two sides
// stay apart and the run gives a valid mesh.
TEST_CASE("pdmesh mesh on a UIUC airfoil with spacing.scale = 4: the merges of scale 1, a valid mesh") {
  const std::string case_file = std::string(PDMESH_SOURCE_DIR) + "/cases/user_corpus/e387/case.toml";
  const auto merges = [](const std::string& output) {
    const std::string key = "healing: ";
    const std::size_t at = output.find(key);
    if (at == std::string::npos || output.find(" merged vertices", at) == std::string::npos) return 0;
    return std::stoi(output.substr(at + key.size()));
  };
  const auto dir = pdmesh_test::fresh_dir("heal_scale4");
  const auto one =
      pdmesh_test::run_pdmesh("mesh '" + case_file + "' --iterations 0 --formats msh --out '" + dir.string() + "'");
  INFO(one.output);
  REQUIRE(one.status == 0);
  REQUIRE(merges(one.output) > 0);
  std::filesystem::remove_all(dir);
  const auto four =
      pdmesh_test::run_pdmesh("mesh '" + case_file + "' --set spacing.scale=4 --out '" + dir.string() + "'");
  INFO(four.output);
  REQUIRE(four.status == 0);
  CHECK(merges(four.output) == merges(one.output));
  CHECK(min_angle(pdmesh_test::slurp(dir / "quality.json")) >= 30.0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("the report: one line per kind with the worst instance, and the JSON object") {
  std::vector<RawCurve> curves = read_curve_file(data("merged.crv"));
  RawCurve island = read_curve_file(data("island.crv")).back();
  curves.push_back(island);
  const HealResult r = heal_curves(curves);
  const std::vector<std::string> lines = heal_report_lines(r);
  REQUIRE(lines.size() == 2);
  CHECK(lines[0].find("merged vertices") != std::string::npos);
  CHECK(lines[0].find("merged.crv:") != std::string::npos);
  CHECK(lines[1].find("1 islands dropped") != std::string::npos);
  const std::string json = heal_json(r);
  pdmesh_test::JsonCheck check;
  CHECK(check.valid(json));
  CHECK(json.find("\"island\": 1") != std::string::npos);
  CHECK(json.find("\"removed\": [[8000, 5000]") != std::string::npos);
}

TEST_CASE("short arcs between critical points get sources of their length") {
  for (const std::string& file : {data("blunt_te.crv"), data("tiny_edge.crv")}) {
    INFO(file);
    const Geometry g = build_geometry(read_curve_file(file));
    const GeometryTree tree(g);
    const BoundarySpacing base(tree);
    const std::vector<PointSource> s = short_arc_sources(g, base);
    REQUIRE(s.size() == 2);
    CHECK(s[0].q < 0.003);
    CHECK(dist(s[0].p, s[1].p) == Approx(s[0].q));
  }
  // Arcs as long as their neighbours: none.
  const Geometry g =
      build_geometry(read_curve_file(std::string(PDMESH_SOURCE_DIR) + "/cases/corpus/coastline/coast.crv"));
  const GeometryTree tree(g);
  CHECK(short_arc_sources(g, BoundarySpacing(tree)).empty());
}

TEST_CASE("short arcs are judged against the field the run places nodes by: spacing.scale times the base") {
  // A 3 x 0.3 rectangle, its long sides in segments of 1: the short sides (one segment each, between
  // two corners) are 0.3 beside 1, not short at scale 1 (4 x 0.3 > 1), short at scale 2.
  RawCurve box;
  box.points = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 0.3}, {2, 0.3}, {1, 0.3}, {0, 0.3}, {0, 0}};
  box.file = "memory";
  const Geometry g = build_geometry(std::vector<RawCurve>{box});
  const GeometryTree tree(g);
  const BoundarySpacing base(tree);
  CHECK(short_arc_sources(g, base).empty());
  const std::vector<PointSource> s = short_arc_sources(g, base, 2.0);
  REQUIRE(s.size() == 4);
  for (const PointSource& p : s) CHECK(p.q == Approx(0.3));
}

TEST_CASE("geometry.heal: on in best, off in the thesis preset, a file's value wins, a non-boolean is refused") {
  const std::filesystem::path source = "/cases/demo/case.toml";
  const std::string minimal = "[geometry]\nfiles = [\"a.crv\"]\n";
  CHECK(parse_case_text(minimal, source).geometry.heal);
  CHECK_FALSE(parse_case_text("preset = \"thesis\"\n" + minimal, source).geometry.heal);
  CHECK(parse_case_text("preset = \"thesis\"\n" + minimal + "heal = true\n", source).geometry.heal);
  CHECK_FALSE(parse_case_text(minimal + "heal = false\n", source).geometry.heal);
  CHECK_FALSE(case_for_geometry_file("a.crv", {parse_set_option("geometry.heal=false")}).geometry.heal);
  CHECK_THROWS_AS(parse_case_text(minimal + "heal = 1\n", source), InputError);
}

// Whole runs of the command (best preset, defaults).
TEST_CASE("pdmesh mesh on each defect: min angle >= 20 after default healing, each change reported") {
  struct Case {
    const char* file;
    const char* line;  // the stderr line's kind
    const char* json;  // its quality.json count
  };
  for (const Case c : {Case{"merged.crv", "merged vertices", "\"merge\": 4"},
                       Case{"inlet.crv", "1 inlets closed", "\"inlet_closed\": 1"},
                       Case{"spike.crv", "1 spikes removed", "\"spike\": 1"},
                       Case{"island.crv", "1 islands dropped", "\"island\": 1"}}) {
    INFO(c.file);
    const auto dir = pdmesh_test::fresh_dir(std::string("heal_") + c.file);
    const auto r = pdmesh_test::run_pdmesh("mesh '" + data(c.file) + "' --out '" + dir.string() + "'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find(std::string("healing: ")) != std::string::npos);
    CHECK(r.output.find(c.line) != std::string::npos);
    const std::string json = pdmesh_test::slurp(dir / "quality.json");
    CHECK(json.find(c.json) != std::string::npos);
    pdmesh_test::JsonCheck check;
    CHECK(check.valid(json));
    CHECK(min_angle(json) >= 20.0);
    CHECK(std::filesystem::exists(dir / "healing.png"));
    std::filesystem::remove_all(dir);
  }
}

TEST_CASE("geometry.heal = false meshes the input exactly: no change, no report, no picture") {
  const auto dir = pdmesh_test::fresh_dir("heal_off");
  const auto r = pdmesh_test::run_pdmesh("mesh '" + data("inlet.crv") + "' --set geometry.heal=false --out '" +
                                         dir.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("healing:") == std::string::npos);
  // The inlet is still there: the input's 67 segments and area, 20 km x 10 km and 100 m x 3 km.
  CHECK(r.output.find("geometry: 1 curves, 67 segments, 1 loops, area 2.003e+08") != std::string::npos);
  const std::string json = pdmesh_test::slurp(dir / "quality.json");
  CHECK(json.find("\"healing\"") == std::string::npos);
  CHECK(!std::filesystem::exists(dir / "healing.png"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("the field follows a short segment that is kept: min angle >= 30 with healing on and off") {
  for (const std::string& file : {data("blunt_te.crv"), data("tiny_edge.crv")}) {
    for (const std::string heal : {"true", "false"}) {
      INFO(file << " heal = " << heal);
      const auto dir = pdmesh_test::fresh_dir("heal_short_arc");
      const auto r = pdmesh_test::run_pdmesh("mesh '" + file + "' --set geometry.heal=" + heal + " --out '" +
                                             dir.string() + "' -q");
      INFO(r.output);
      REQUIRE(r.status == 0);
      CHECK(min_angle(pdmesh_test::slurp(dir / "quality.json")) >= 30.0);
      std::filesystem::remove_all(dir);
    }
  }
}
