// Sizes as users state them (spacing/refine_regions.hpp): spacing.size (--size) gives edges of about
// that length on a square, each [[refine]] region brings the edges inside it to about its size, and
// bad values are input errors naming the key and the value (exit 2, nothing written).
#include <catch2/catch.hpp>

#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>

#include "core/errors.hpp"
#include "io/msh_reader.hpp"
#include "mesh_measures.hpp"
#include "run_pdmesh.hpp"
#include "source_dir.hpp"
#include "spacing/refine_regions.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using pdmesh_test::run_pdmesh;

namespace {

const std::string kSquare = pdmesh::test::source_dir() + "/tests/data/geometry/unit_square.crv";

// Meshes the unit square with `extra` appended to its case file; the mesh read back.
Mesh mesh_square(const std::string& tag, const std::string& extra) {
  const auto dir = pdmesh_test::fresh_dir(tag);
  std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"" << kSquare << "\"]\n" << extra;
  const auto r = run_pdmesh("mesh '" + dir.string() + "' -q --formats msh --out '" + (dir / "out").string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  MeshReadReport report;
  Mesh m = read_msh(dir / "out" / "mesh.msh", report);
  std::filesystem::remove_all(dir);
  return m;
}

}  // namespace

TEST_CASE("region sizes: inside each shape its size, outside +inf, the field is the minimum with the base") {
  RefineRegion box{.shape = RegionShape::Box, .size = 0.1, .label = "r"};
  box.box.add({0.0, 0.0});
  box.box.add({1.0, 2.0});
  CHECK(region_size(box, {0.5, 1.5}) == 0.1);
  CHECK(std::isinf(region_size(box, {1.5, 1.5})));
  RefineRegion disc{.shape = RegionShape::Disc, .size = 0.2, .centre = {1.0, 1.0}, .radius = 0.5, .label = "r"};
  CHECK(region_size(disc, {1.3, 1.3}) == 0.2);
  CHECK(std::isinf(region_size(disc, {1.4, 1.4})));
  RefineRegion line{
      .shape = RegionShape::Polyline, .size = 0.3, .radius = 0.1, .points = {{0, 0}, {1, 0}, {1, 1}}, .label = "r"};
  CHECK(region_size(line, {0.5, 0.09}) == 0.3);
  CHECK(region_size(line, {0.91, 0.5}) == 0.3);
  CHECK(std::isinf(region_size(line, {0.5, 0.11})));
  RefineRegion points{
      .shape = RegionShape::Points, .size = 0.4, .radius = 0.1, .points = {{0, 0}, {1, 0}}, .label = "r"};
  CHECK(region_size(points, {0.95, 0.0}) == 0.4);
  CHECK(std::isinf(region_size(points, {0.5, 0.0})));
  const RegionSpacing field(std::make_unique<UniformSpacing>(0.25), {disc, points});
  CHECK(field.at({1.0, 1.0}) == 0.2);
  CHECK(field.at({0.0, 0.0}) == 0.25);  // the base is finer than the points' 0.4
  CHECK(field.at({3.0, 3.0}) == 0.25);
}

TEST_CASE("bad regions name the key and the value") {
  RefineRegion box{.shape = RegionShape::Box, .size = 0.1, .label = "refine[2]"};
  box.box.lo = {1.0, 0.0};
  box.box.hi = {0.0, 1.0};
  CHECK_THROWS_WITH(check_refine_region(box), Catch::Contains("refine[2].box = [1, 0, 0, 1]"));
  RefineRegion disc{.shape = RegionShape::Disc, .size = -1.0, .radius = 1.0, .label = "refine[0]"};
  CHECK_THROWS_WITH(check_refine_region(disc), Catch::Contains("refine[0].size = -1"));
  disc.size = 1.0;
  disc.radius = 0.0;
  CHECK_THROWS_WITH(check_refine_region(disc), Catch::Contains("refine[0].radius = 0"));
  RefineRegion line{
      .shape = RegionShape::Polyline, .size = 0.1, .radius = 1.0, .points = {{0, 0}}, .label = "refine[1]"};
  CHECK_THROWS_WITH(check_refine_region(line), Catch::Contains("at least 2 points"));
}

// The best preset relaxes at spacing.relax_scale x q (1.09), calibrated so that graded meshes average
// q; a uniform square's lattice packs less tightly and averages 1.05-1.09 H (docs/spacing.md, "The node count").
TEST_CASE("spacing.size H on a square: mean edge within 10 % of H") {
  for (const double h : {0.05, 0.1}) {
    const Mesh m =
        mesh_square("size_" + std::to_string(static_cast<int>(h * 100)), fmt::format("[spacing]\nsize = {}\n", h));
    const auto e = pdmesh_test::mean_edge(m, [](Vec2) { return true; });
    INFO("H = " << h << ": mean edge " << e.mean << " over " << e.count << " edges");
    CHECK(e.mean >= 0.97 * h);
    CHECK(e.mean <= 1.10 * h);
    CHECK(pdmesh_test::min_angle_deg(m) >= 30.0);
  }
}

TEST_CASE("each refinement region brings the edges inside it to about its size") {
  const std::string base = "[spacing]\nsize = 0.08\n";
  struct Region {
    std::string toml;
    std::function<bool(Vec2)> deep_inside;  // well inside the region (away from its graded edge)
  };
  const std::vector<Region> regions = {
      {"[[refine]]\nshape = \"box\"\nbox = [0.3, 0.3, 0.7, 0.7]\nsize = 0.02\n",
       [](Vec2 p) { return p.x > 0.35 && p.x < 0.65 && p.y > 0.35 && p.y < 0.65; }},
      {"[[refine]]\nshape = \"disc\"\ncentre = [0.5, 0.5]\nradius = 0.2\nsize = 0.02\n",
       [](Vec2 p) { return std::hypot(p.x - 0.5, p.y - 0.5) < 0.16; }},
      {"[[refine]]\nshape = \"points\"\npoints = [[0.3, 0.5], [0.7, 0.5]]\nradius = 0.12\nsize = 0.02\n",
       [](Vec2 p) { return std::hypot(p.x - 0.3, p.y - 0.5) < 0.09 || std::hypot(p.x - 0.7, p.y - 0.5) < 0.09; }},
      {"[[refine]]\nshape = \"polyline\"\npoints = [[0.2, 0.5], [0.8, 0.5]]\nradius = 0.1\nsize = 0.02\n",
       [](Vec2 p) { return p.x > 0.25 && p.x < 0.75 && std::fabs(p.y - 0.5) < 0.07; }},
  };
  int k = 0;
  for (const Region& r : regions) {
    const Mesh m = mesh_square("refine_" + std::to_string(k++), base + r.toml);
    const auto in = pdmesh_test::mean_edge(m, r.deep_inside);
    // The corners lie beyond the gradation's reach from every region ((0.08 - 0.02) / 0.2 = 0.3).
    const auto out = pdmesh_test::mean_edge(
        m, [](Vec2 p) { return std::min(p.x, 1.0 - p.x) < 0.12 && std::min(p.y, 1.0 - p.y) < 0.12; });
    INFO(r.toml << "inside: " << in.mean << " over " << in.count << " edges; in the corners " << out.mean);
    REQUIRE(in.count > 20);
    CHECK(in.mean >= 0.8 * 0.02);
    CHECK(in.mean <= 1.1 * 0.02);
    // Away from the region the base size holds. The corners' mean edge moves by about 1 % with any change
    // of the field's tree (the whole square relaxes again): 0.0794-0.0817 over the four regions and
    // seven tolerances of 0.0097-0.0103.
    CHECK(out.mean > 0.8 * 0.08);
    CHECK(out.mean <= 1.03 * 0.08);
    CHECK(pdmesh_test::min_angle_deg(m) >= 30.0);
  }
}

TEST_CASE("bad sizes and regions in a case file exit 2 naming the key and the value, writing nothing") {
  const auto dir = pdmesh_test::fresh_dir("refine_bad");
  const auto out = dir / "out";
  for (const auto& [text, named] : std::vector<std::pair<std::string, std::string>>{
           {"[spacing]\nsize = -0.1\n", "spacing.size must be > 0, got -0.1"},
           {"[spacing]\nsize = 0.1\nexpression = \"0.1\"\n", "spacing.size is set but spacing.field is 'expression'"},
           {"[[refine]]\nshape = \"box\"\nbox = [0.7, 0.3, 0.3, 0.7]\nsize = 0.02\n",
            "refine[0].box = [0.7, 0.3, 0.3, 0.7]"},
           {"[[refine]]\nshape = \"disc\"\ncentre = [0.5, 0.5]\nradius = 0.2\nsize = -1\n", "refine[0].size = -1"},
           {"[[refine]]\nshape = \"star\"\nsize = 1\n",
            "refine[0].shape must be one of box, disc, points, polyline, region, got 'star'"},
           {"[[refine]]\nshape = \"disc\"\ncentre = [0.5, 0.5]\nsize = 0.1\n", "refine[0].radius is required"},
           {"[[refine]]\nshape = \"box\"\nbox = [0, 0, 1, 1]\nradius = 1\nsize = 0.1\n",
            "refine[0].radius does not go with"},
           {"[[refine]]\nshape = \"disc\"\ncentre = [0.5, 0.5]\nradius = 0.2\nsize = 0.1\nsise = 1\n",
            "did you mean 'refine.size'"},
       }) {
    std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"" << kSquare << "\"]\n" << text;
    const auto r = run_pdmesh("mesh '" + dir.string() + "' --out '" + out.string() + "'");
    INFO(text << r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find(named) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
  }
  const auto r = run_pdmesh("mesh '" + kSquare + "' --size 0 --out '" + out.string() + "'");
  CHECK(r.status == 2);
  CHECK(r.output.find("--size 0: spacing.size must be > 0, got 0") != std::string::npos);
  std::filesystem::remove_all(dir);
}
