// Quality per region: quality.json's "regions" (one entry per regional attribute, the top level's
// figures on the region's triangles) and `pdmesh quality`'s row per region, on a .poly with two regions
// one of which is refined, on a Gmsh file with two named physical surfaces, and none for a mesh
// without regions.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "app/cli/quality_command.hpp"
#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "io/quality_report.hpp"
#include "io/region_quality.hpp"
#include "quality_json.hpp"
#include "run_pdmesh.hpp"
#include "source_dir.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using pdmesh_test::read_quality_json;

namespace {

const std::string kData = pdmesh::test::source_dir() + "/tests/data/";

// The checks every two-region quality.json passes: the counts add up, each region's smallest angle is
// no smaller than the whole's and one region has it, its largest no larger and one region has it.
void check_regions_add_up(const nlohmann::json& q) {
  REQUIRE(q.contains("regions"));
  const nlohmann::json& regions = q["regions"];
  REQUIRE(regions.size() == 2);
  long long triangles = 0;
  bool has_min = false, has_max = false;
  const double min_angle = q["included_angle"]["min"].get<double>();
  const double max_angle = q["included_angle"]["max"].get<double>();
  for (const auto& r : regions) {
    triangles += r["triangles"].get<long long>();
    const double r_min = r["included_angle"]["min"].get<double>();
    const double r_max = r["included_angle"]["max"].get<double>();
    CHECK(r_min >= min_angle);
    CHECK(r_max <= max_angle);
    has_min = has_min || r_min == min_angle;
    has_max = has_max || r_max == max_angle;
    CHECK(r["aspect_ratio"]["max"].get<double>() <= q["aspect_ratio"]["max"].get<double>());
    CHECK(r["points"].get<long long>() < q["points"].get<long long>());
  }
  CHECK(triangles == q["triangles"].get<long long>());
  CHECK(has_min);
  CHECK(has_max);
  CHECK(regions[0]["attribute"].get<double>() < regions[1]["attribute"].get<double>());
}

}  // namespace

TEST_CASE("quality.json per region: a .poly's two regions, the right one refined", "[quality][regions]") {
  const fs::path dir = pdmesh_test::fresh_dir("region_quality_poly");
  const fs::path case_file = dir / "case.toml";
  std::ofstream(case_file) << "name = \"two_regions\"\npreset = \"best\"\n\n[geometry]\nfiles = [\"" << kData
                           << "mesh_geometry/hole_two_regions.poly\"]\n"
                           << "region_names = { 1 = \"steel\", 2 = \"copper\" }\n\n[spacing]\nsize = 0.5\n\n"
                           << "[[refine]]\nshape = \"region\"\nregion = \"copper\"\nsize = 0.15\n\n"
                           << "[simulation]\ndevice = \"host\"\n\n[output]\nformats = [\"msh\"]\n";
  CaseConfig c = load_case_file(case_file);
  c.out_dir = dir / "out";
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const nlohmann::json q = read_quality_json(c.out_dir / "quality.json");
  check_regions_add_up(q);
  const nlohmann::json& steel = q["regions"][0];
  const nlohmann::json& copper = q["regions"][1];
  CHECK(steel["attribute"].get<double>() == 1.0);
  CHECK(steel["name"].get<std::string>() == "steel");
  CHECK(copper["attribute"].get<double>() == 2.0);
  CHECK(copper["name"].get<std::string>() == "copper");
  // Copper (a quarter of the area at less than a third of the size) has the more triangles.
  CHECK(copper["triangles"].get<long long>() > steel["triangles"].get<long long>());
  // Conformance per region: the edges of its triangles, the interface's in both regions.
  const long long edges = q["spacing_conformance"]["edges"].get<long long>();
  const long long steel_edges = steel["spacing_conformance"]["edges"].get<long long>();
  const long long copper_edges = copper["spacing_conformance"]["edges"].get<long long>();
  CHECK(steel_edges + copper_edges > edges);
  CHECK(steel_edges < edges);
  CHECK(copper_edges < edges);
  for (const auto* r : {&steel, &copper}) {
    const double mean = (*r)["spacing_conformance"]["mean"].get<double>();
    CHECK(mean > 0.5);
    CHECK(mean < 1.5);
  }
  // The histograms count the region's triangles.
  long long binned = copper["histograms"]["min_angle"]["overflow"].get<long long>();
  for (const auto& n : copper["histograms"]["min_angle"]["counts"]) binned += n.get<long long>();
  CHECK(binned == copper["triangles"].get<long long>());

  // The run's mesh file read back by `pdmesh quality`: the same regions and names, a row each.
  std::ostringstream text, err;
  REQUIRE(run_quality((c.out_dir / "mesh.msh").string(), std::nullopt, (dir / "q.json").string(), text, err) == 0);
  const nlohmann::json back = read_quality_json(dir / "q.json");
  check_regions_add_up(back);
  CHECK(back["regions"][0]["name"].get<std::string>() == "steel");
  CHECK(back["regions"][1]["name"].get<std::string>() == "copper");
  CHECK(back["regions"][1]["triangles"] == copper["triangles"]);
  CHECK(back["regions"][1]["included_angle"] == copper["included_angle"]);
  CHECK(back["spacing_conformance"].is_null());
  CHECK(back["regions"][0]["spacing_conformance"].is_null());
  INFO(text.str());
  CHECK(text.str().find("Per region (2 regions):") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("pdmesh quality on a Gmsh file with two physical surfaces prints a row per region", "[quality][regions]") {
  // tests/data/region_quality/make_two_materials.py: "steel" (attribute 1) and the finer "copper" (2).
  const std::string file = kData + "region_quality/two_materials.msh";
  const fs::path json = pdmesh_test::fresh_path("region_quality_gmsh") += ".json";
  const auto r = pdmesh_test::run_pdmesh("quality '" + file + "' --json '" + json.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const nlohmann::json q = read_quality_json(json);
  check_regions_add_up(q);
  const nlohmann::json& steel = q["regions"][0];
  const nlohmann::json& copper = q["regions"][1];
  CHECK(steel["name"].get<std::string>() == "steel");
  CHECK(copper["name"].get<std::string>() == "copper");
  CHECK(copper["triangles"].get<long long>() > steel["triangles"].get<long long>());
  // The rows follow the table: a header, then one line per region ending in its name, with its
  // triangles and smallest angle as the JSON has them.
  const auto lines = pdmesh_test::lines_of(r.output);
  const auto header = std::find_if(lines.begin(), lines.end(),
                                   [](const std::string& l) { return l.rfind("Per region (2 regions):", 0) == 0; });
  REQUIRE(header != lines.end());
  REQUIRE(lines.end() - header >= 4);
  CHECK(header[1].find("triangles") != std::string::npos);
  CHECK(header[1].find("angle MIN") != std::string::npos);
  for (int k = 0; k < 2; ++k) {
    const nlohmann::json& region = q["regions"][static_cast<std::size_t>(k)];
    const std::string& row = header[2 + k];
    const std::string name = region["name"].get<std::string>();
    CHECK(row.size() > name.size());
    CHECK(row.substr(row.size() - name.size()) == name);
    std::istringstream fields(row);
    double attribute = 0.0, min_angle = 0.0;
    long long triangles = 0, points = 0;
    fields >> attribute >> triangles >> points >> min_angle;
    CHECK(attribute == region["attribute"].get<double>());
    CHECK(triangles == region["triangles"].get<long long>());
    CHECK(min_angle == Approx(region["included_angle"]["min"].get<double>()).margin(0.005));
  }
  fs::remove(json);
}

TEST_CASE("a mesh without regions has no regions key and no region rows", "[quality][regions]") {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  QualitySummary s = summarize_quality(m);
  const std::string before = quality_json(s, "m");
  add_region_quality(m, s);
  CHECK(s.regions.empty());
  CHECK(quality_json(s, "m") == before);
  CHECK(before.find("\"regions\"") == std::string::npos);
  CHECK(format_region_table(s).empty());
  // Attribute 0 everywhere, no names: still no regions.
  m.region = {0.0, 0.0};
  CHECK_FALSE(has_regions(m));
  add_region_quality(m, s);
  CHECK(s.regions.empty());
  // One named region is a region (a Gmsh file's one named surface): an entry, but no rows to print.
  m.region = {3.0, 3.0};
  m.region_names = {{3.0, "fluid"}};
  add_region_quality(m, s);
  REQUIRE(s.regions.size() == 1);
  CHECK(s.regions[0].name == "fluid");
  CHECK(s.regions[0].quality.triangles == 2);
  CHECK(s.regions[0].quality.min_angle == s.min_angle);
  CHECK(format_region_table(s).empty());
}

TEST_CASE("attribute 0 is an entry of its own only where triangles have it", "[quality][regions]") {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
  m.triangles = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  m.region = {0.0, 0.0, 2.0, 2.0};
  QualitySummary s = summarize_quality(m, [](Vec2) { return 1.0; });
  add_region_quality(m, s, [](Vec2) { return 1.0; });
  REQUIRE(s.regions.size() == 2);
  CHECK(s.regions[0].attribute == 0.0);
  CHECK(s.regions[0].name == "region_0");
  CHECK(s.regions[1].attribute == 2.0);
  CHECK(s.regions[1].name == "region_2");
  CHECK(s.regions[0].quality.points == 4);
  // The unit squares' edges: 5 each, the shared one in both; the whole mesh has 9.
  CHECK(s.spacing.edges == 9);
  CHECK(s.regions[0].quality.spacing.edges == 5);
  CHECK(s.regions[1].quality.spacing.edges == 5);
  const std::string json = quality_json(s, "m");
  CHECK(json.find("\"regions\": [") != std::string::npos);
  const nlohmann::json q = nlohmann::json::parse(json);
  check_regions_add_up(q);
  m.region = {1.0, 1.0, 2.0, 2.0};
  add_region_quality(m, s);
  REQUIRE(s.regions.size() == 2);
  CHECK(s.regions[0].attribute == 1.0);
  // Without a q the regions have no conformance, even where the whole has one.
  CHECK_FALSE(s.regions[0].quality.has_spacing);
  CHECK(format_region_table(s).find("region_1\n") != std::string::npos);
}
