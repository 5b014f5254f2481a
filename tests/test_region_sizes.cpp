// Sizes per subdomain (spacing/subdomains.hpp, spacing/refine_regions.hpp): the faces of a
// geometry's curves with their regional attributes, [[refine]] shape = "region" by attribute, name
// or point, a .poly file's maximum areas, and the input errors (exit 2, the case file's line).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "core/errors.hpp"
#include "geometry/geometry_files.hpp"
#include "io/msh_reader.hpp"
#include "run_pdmesh.hpp"
#include "source_dir.hpp"
#include "spacing/refine_regions.hpp"
#include "spacing/subdomains.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using pdmesh_test::run_pdmesh;

namespace {

// A 4 x 4 square with a 1 x 1 hole at [1, 2]^2, split at x = 3 by a constraint: attribute 1 on the
// left (with the hole), 2 on the right.
const std::string kTwoRegions = pdmesh::test::source_dir() + "/tests/data/mesh_geometry/hole_two_regions.poly";

class Unit final : public SpacingField {
 public:
  double at(Vec2) const override { return 1.0; }
};

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct RegionStats {
  int triangles = 0;
  double area = 0.0, max_area = 0.0, edge = 0.0, max_edge = 0.0;  // edge: the mean edge length
};

// Per regional attribute of `m`: the triangles, their total and largest area and the mean edge.
std::map<double, RegionStats> stats_by_region(const Mesh& m) {
  std::map<double, RegionStats> out;
  REQUIRE(m.region.size() == m.triangles.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Vec2 a = m.points[m.triangles[t][0]], b = m.points[m.triangles[t][1]], c = m.points[m.triangles[t][2]];
    const double area = 0.5 * std::abs(cross(b - a, c - a));
    RegionStats& s = out[m.region[t]];
    s.triangles += 1;
    s.area += area;
    s.max_area = std::max(s.max_area, area);
    s.edge += (dist(a, b) + dist(b, c) + dist(c, a)) / 3.0;
    s.max_edge = std::max({s.max_edge, dist(a, b), dist(b, c), dist(c, a)});
  }
  for (auto& [attribute, s] : out) s.edge /= s.triangles;
  return out;
}

struct Run {
  int status = 0;
  std::string output;
  Mesh mesh;
  bool wrote = false;
};

// Runs `pdmesh mesh` on a case of the two-region square (spacing.size 0.5) with `extra` appended.
Run run_case(const std::string& tag, const std::string& extra, const std::string& poly = kTwoRegions) {
  const auto dir = pdmesh_test::fresh_dir(tag);
  std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"" << poly << "\"]\n\n[spacing]\nsize = 0.5\n\n"
                                   << "[simulation]\ndevice = \"host\"\n\n"
                                   << extra;
  Run run;
  const auto r = run_pdmesh("mesh '" + dir.string() + "' -q --formats msh --out '" + (dir / "out").string() + "'");
  run.status = r.status;
  run.output = r.output;
  run.wrote = std::filesystem::exists(dir / "out" / "mesh.msh");
  if (run.status == 0 && run.wrote) {
    MeshReadReport report;
    run.mesh = read_msh(dir / "out" / "mesh.msh", report);
  }
  std::filesystem::remove_all(dir);
  return run;
}

}  // namespace

TEST_CASE("subdomains: the faces of the curves with their attributes, closed at the curves") {
  const Geometry g = read_geometry({kTwoRegions}, {});
  REQUIRE(g.regions.size() == 2);
  const Subdomains s(g);
  const std::vector<int> left = s.faces_with_attribute(1), right = s.faces_with_attribute(2);
  REQUIRE(left.size() == 1);
  REQUIRE(right.size() == 1);
  CHECK(left != right);
  CHECK(s.face_at({0.5, 0.5}) == left[0]);
  CHECK(s.face_at({3.5, 3.9}) == right[0]);
  CHECK(s.face_at({3.0, 2.0}) == -1);  // on the interface
  CHECK(s.faces_with_attribute(3).empty());
  // The left region surrounds the hole: points in the hole are in neither.
  CHECK(s.in_any(left, {0.5, 3.5}));
  CHECK(s.in_any(left, {2.9, 0.1}));
  CHECK_FALSE(s.in_any(left, {1.5, 1.5}));
  CHECK_FALSE(s.in_any(right, {1.5, 1.5}));
  CHECK_FALSE(s.in_any(left, {3.5, 0.5}));
  CHECK(s.in_any(right, {3.5, 0.5}));
  CHECK_FALSE(s.in_any(right, {2.5, 0.5}));
  // Closed: the interface belongs to both, the hole's edge and the outer boundary to the left one.
  CHECK(s.in_any(left, {3.0, 2.0}));
  CHECK(s.in_any(right, {3.0, 2.0}));
  CHECK(s.in_any(left, {1.0, 1.5}));
  CHECK(s.in_any(left, {0.0, 2.0}));
  CHECK_FALSE(s.in_any(right, {0.0, 2.0}));
  // Outside the square.
  CHECK_FALSE(s.in_any(left, {-0.1, 2.0}));
  CHECK_FALSE(s.in_any(right, {4.1, 2.0}));
}

TEST_CASE("subdomains: a region named, and the refusals of regions the geometry does not have") {
  Geometry g = read_geometry({kTwoRegions}, {});
  for (GeometryRegion& r : g.regions) r.name = r.attribute == 2 ? "copper" : "steel";
  const Subdomains s(g);
  CHECK(s.faces_named("copper") == s.faces_with_attribute(2));
  CHECK(s.faces_named("steel") == s.faces_with_attribute(1));
  CHECK(s.faces_named("iron").empty());

  RefineRegion copper{.shape = RegionShape::Subdomain, .size = 0.1, .region_name = "copper", .label = "refine[0]"};
  const RegionSpacing field(std::make_unique<Unit>(), {copper}, &g);
  CHECK(field.at({3.5, 0.5}) == 0.1);
  CHECK(field.at({3.0, 1.0}) == 0.1);  // on the interface
  CHECK(field.at({0.5, 0.5}) == 1.0);
  CHECK(field.at({1.5, 1.5}) == 1.0);  // in the hole

  RefineRegion seven{.shape = RegionShape::Subdomain, .size = 0.1, .attribute = 7.0, .label = "refine[0]"};
  CHECK_THROWS_WITH(RegionSpacing(std::make_unique<Unit>(), {seven}, &g),
                    Catch::Contains("refine[0].region = 7: no region of the geometry has this attribute") &&
                        Catch::Contains("its regions: 1 \"steel\", 2 \"copper\""));
  RefineRegion iron{.shape = RegionShape::Subdomain, .size = 0.1, .region_name = "iron", .label = "refine[1]"};
  CHECK_THROWS_WITH(RegionSpacing(std::make_unique<Unit>(), {iron}, &g),
                    Catch::Contains("refine[1].region = \"iron\": no region of the geometry has this name"));
  RefineRegion on_curve{.shape = RegionShape::Subdomain, .size = 0.1, .at = Vec2{3.0, 1.0}, .label = "refine[2]"};
  CHECK_THROWS_WITH(RegionSpacing(std::make_unique<Unit>(), {on_curve}, &g),
                    Catch::Contains("refine[2]: the point (3, 1) lies on a curve or outside every loop"));
  RefineRegion both{
      .shape = RegionShape::Subdomain, .size = 0.1, .attribute = 1.0, .at = Vec2{0.5, 0.5}, .label = "refine[3]"};
  CHECK_THROWS_AS(RegionSpacing(std::make_unique<Unit>(), {both}, &g), InputError);
  CHECK_THROWS_AS(RegionSpacing(std::make_unique<Unit>(), {copper}, nullptr), InputError);
}

TEST_CASE("[[refine]] shape = \"region\": the region's triangles at its size, the other region's at the base") {
  const Run base = run_case("region_size_base", "");
  REQUIRE(base.status == 0);
  const auto before = stats_by_region(base.mesh);
  // By attribute, by name and by a point in it: the same subdomain.
  for (const std::string& selector :
       {std::string("region = 2"), std::string("point = [3.5, 2.0]"), std::string("region = \"copper\"")}) {
    const bool named = selector.find("copper") != std::string::npos;
    std::string extra = "[[refine]]\nshape = \"region\"\n" + selector + "\nsize = 0.1\n";
    if (named) extra = "[geometry.region_names]\n2 = \"copper\"\n\n" + extra;
    const Run run = run_case("region_size", extra);
    INFO(selector << "\n" << run.output);
    REQUIRE(run.status == 0);
    // A named region is written under the writer's tag (docs/mesh-formats.md, "Regions"): found by its name.
    double fine = 2.0;
    for (const RegionName& r : run.mesh.region_names)
      if (named && r.name == "copper") fine = r.attribute;
    const auto after = stats_by_region(run.mesh);
    REQUIRE(after.size() == 2);
    REQUIRE(after.count(fine) == 1);
    const RegionStats& coarse = after.begin()->first == fine ? after.rbegin()->second : after.begin()->second;
    // The right region (1 x 4) at size 0.1: edges near 0.1, some 900 triangles; before, at 0.5, few.
    CHECK(after.at(fine).edge < 0.13);
    CHECK(after.at(fine).edge > 0.07);
    CHECK(after.at(fine).triangles > 10 * before.at(2).triangles);
    // The left region keeps its coarse triangles away from the interface (graded towards it).
    CHECK(coarse.edge > 2.0 * after.at(fine).edge);
    CHECK(coarse.max_edge > 0.8 * before.at(1).max_edge);
  }
}

TEST_CASE("a .poly file's maximum areas size their subdomains, said in a note") {
  const auto dir = pdmesh_test::fresh_dir("max_area_poly");
  std::string poly = slurp(kTwoRegions);
  const std::string line = "2 3.5 0.5 2 0";
  REQUIRE(poly.find(line) != std::string::npos);
  poly.replace(poly.find(line), line.size(), "2 3.5 0.5 2 0.004");
  std::ofstream(dir / "capped.poly") << poly;
  const Run run = run_case("max_area", "", (dir / "capped.poly").string());
  INFO(run.output);
  REQUIRE(run.status == 0);
  CHECK(run.output.find("each such subdomain is sized so that its largest triangles have about that area") !=
        std::string::npos);
  const auto stats = stats_by_region(run.mesh);
  REQUIRE(stats.count(2) == 1);
  // 4 square units with triangles of at most about 0.004.
  const double mean = stats.at(2).area / stats.at(2).triangles;
  CHECK(mean < 0.8 * 0.004);
  CHECK(mean > 0.4 * 0.004);
  CHECK(stats.at(2).max_area < 1.1 * 0.004);
  std::filesystem::remove_all(dir);
}

TEST_CASE("[[refine]] shape = \"region\": bad tables are input errors at their line, nothing written") {
  struct Bad {
    std::string extra, says;
  };
  for (const Bad& bad : {
           Bad{"[[refine]]\nshape = \"region\"\nsize = 0.1\n", "takes one of region"},
           Bad{"[[refine]]\nshape = \"region\"\nregion = 1\npoint = [0.5, 0.5]\nsize = 0.1\n", "takes one of region"},
           Bad{"[[refine]]\nshape = \"region\"\nregion = 1\nradius = 0.5\nsize = 0.1\n",
               "refine[0].radius does not go with shape = \"region\""},
           Bad{"[[refine]]\nshape = \"region\"\nregion = 9\nsize = 0.1\n",
               "refine[0].region = 9: no region of the geometry has this attribute"},
           Bad{"[[refine]]\nshape = \"region\"\nregion = \"iron\"\nsize = 0.1\n",
               "refine[0].region = \"iron\": no region of the geometry has this name"},
           Bad{"[[refine]]\nshape = \"region\"\npoint = [3.0, 1.0]\nsize = 0.1\n", "lies on a curve"},
           Bad{"[[refine]]\nshape = \"region\"\nregion = 1\nsize = -1\n", "size = -1"},
       }) {
    const Run run = run_case("region_size_bad", bad.extra);
    INFO(bad.extra << "\n" << run.output);
    CHECK(run.status == 2);
    CHECK(run.output.find(bad.says) != std::string::npos);
    CHECK(run.output.find("case.toml:") != std::string::npos);
    CHECK_FALSE(run.wrote);
  }
}
