// `pdmesh quality` on meshes with quadrangles: the cells' counts and angles read from the file agree
// with what the layered run's quality.json reports for the same mesh.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>

#include "app/cli/quality_command.hpp"
#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "io/text_file.hpp"
#include "quality_json.hpp"
#include "source_dir.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using pdmesh_test::read_quality_json;

TEST_CASE("quality of a layered run's mesh.msh: its quads and angles as the run's quality.json", "[quality][layers]") {
  const fs::path out = fs::temp_directory_path() / "pdmesh_test_quality_mixed";
  fs::remove_all(out);
  CaseConfig c = load_case_file(pdmesh::test::source_dir() + "/tests/data/layers_naca/case.toml");
  c.out_dir = out;
  c.quiet = true;
  c.output.formats = {"msh"};
  REQUIRE(run_mesh(c) == 0);
  const nlohmann::json run = read_quality_json(out / "quality.json")["boundary_layer"];
  // The run's layer tables together: the cells of the file's "boundary_layer" group.
  long long cells = 0, quads = 0, triangles = 0, above_150 = 0, inverted = 0;
  double max_angle = 0.0;
  for (const auto& t : run["tables"]) {
    cells += t["cells"].get<long long>();
    quads += t["quads"].get<long long>();
    triangles += t["triangles"].get<long long>();
    above_150 += t["angles_above_150"].get<long long>();
    inverted += t["inverted_cells"].get<long long>();
    max_angle = std::max(max_angle, t["max_angle"].get<double>());
  }
  REQUIRE(quads > 0);

  std::ostringstream text, err;
  REQUIRE(run_quality((out / "mesh.msh").string(), std::nullopt, (out / "q.json").string(), text, err) == 0);
  INFO(err.str());
  CHECK(err.str().find("skipped") == std::string::npos);
  const nlohmann::json q = read_quality_json(out / "q.json");
  REQUIRE(q.contains("cells"));
  const nlohmann::json& all = q["cells"]["all"];
  CHECK(q["cells"]["points"].get<long long>() == run["points"].get<long long>());
  CHECK(all["cells"].get<long long>() == run["cells"].get<long long>());
  CHECK(all["quads"].get<long long>() == run["quads"].get<long long>());
  CHECK(q["cells"]["layer_cells"].get<std::string>() == "boundary_layer");
  const nlohmann::json& layer = q["cells"]["layer"];
  CHECK(layer["cells"].get<long long>() == cells);
  CHECK(layer["quads"].get<long long>() == quads);
  CHECK(layer["triangles"].get<long long>() == triangles);
  CHECK(layer["angles_above_150"].get<long long>() == above_150);
  CHECK(layer["inverted_cells"].get<long long>() == inverted);
  CHECK(layer["max_angle"].get<double>() == max_angle);
  // The triangles' table counts the core's triangles and the layer's (the quads are not in it).
  CHECK(q["triangles"].get<long long>() == all["triangles"].get<long long>());
  fs::remove_all(out);
}

TEST_CASE("quality of an MSH 2.2 file with quads: counts, angles, a clockwise quad turned", "[quality]") {
  const fs::path dir = fs::temp_directory_path() / "pdmesh_test_quality_mixed22";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A unit square (counter-clockwise), beside it a trapezoid with corners of 90, 135, 45 and 90
  // degrees written clockwise, and a right triangle over the square; the two quads in
  // "boundary_layer".
  write_text_file(dir / "m.msh",
                  "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 \"domain\"\n"
                  "2 2 \"boundary_layer\"\n$EndPhysicalNames\n$Nodes\n7\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n"
                  "5 2 0 0\n6 3 1 0\n7 0 2 0\n$EndNodes\n$Elements\n3\n1 3 2 2 2 1 2 3 4\n2 3 2 2 2 2 3 6 5\n"
                  "3 2 2 1 1 4 3 7\n$EndElements\n");
  std::ostringstream text, err;
  REQUIRE(run_quality((dir / "m.msh").string(), std::nullopt, (dir / "q.json").string(), text, err) == 0);
  INFO(text.str() + err.str());
  CHECK(err.str().find("turned 1 clockwise quadrangles counter-clockwise") != std::string::npos);
  const nlohmann::json q = read_quality_json(dir / "q.json")["cells"];
  CHECK(q["points"].get<int>() == 7);
  CHECK(q["all"]["cells"].get<int>() == 3);
  CHECK(q["all"]["quads"].get<int>() == 2);
  CHECK(q["all"]["triangles"].get<int>() == 1);
  CHECK(q["all"]["inverted_cells"].get<int>() == 0);
  CHECK(q["layer_cells"].get<std::string>() == "boundary_layer");
  CHECK(q["layer"]["cells"].get<int>() == 2);
  CHECK(q["layer"]["quads"].get<int>() == 2);
  CHECK(q["layer"]["max_angle"].get<double>() == Approx(135.0).epsilon(1e-12));
  CHECK(q["layer"]["angles_above_150"].get<int>() == 0);
  CHECK(read_quality_json(dir / "q.json")["triangles"].get<int>() == 1);
  fs::remove_all(dir);
}
