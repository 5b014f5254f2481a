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
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using pdmesh_test::read_quality_json;

TEST_CASE("quality of a layered run's mesh.msh: its quads and angles as the run's quality.json", "[quality][layers]") {
  const fs::path out = pdmesh_test::fresh_path("quality_mixed");
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
  const fs::path dir = pdmesh_test::fresh_path("quality_mixed22");
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

namespace {

// pdmesh quality of `file` with its JSON: the document, the table and the notes.
struct Measured {
  nlohmann::json q;
  std::string text, err;
};

Measured measure(const fs::path& file) {
  const fs::path json = file.parent_path() / (file.filename().string() + ".json");
  std::ostringstream text, err;
  REQUIRE(run_quality(file.string(), std::nullopt, json.string(), text, err) == 0);
  return {read_quality_json(json), text.str(), err.str()};
}

void check_same_cells(const nlohmann::json& a, const nlohmann::json& b) {
  for (const char* key : {"cells", "quads", "triangles", "angles_above_150", "inverted_cells"})
    CHECK(a[key].get<long long>() == b[key].get<long long>());
  CHECK(a["max_angle"].get<double>() == b["max_angle"].get<double>());
}

}  // namespace

TEST_CASE(
    "quality of one layered run's mesh in msh, vtu, su2 and mesh: the same cells and angles, and its quality.json's "
    "layout",
    "[quality][layers][vtu][su2][medit]") {
  const fs::path out = pdmesh_test::fresh_path("quality_formats");
  fs::remove_all(out);
  CaseConfig c = load_case_file(pdmesh::test::source_dir() + "/tests/data/layers_naca/case.toml");
  c.out_dir = out;
  c.quiet = true;
  c.output.formats = {"msh", "vtu", "su2", "mesh"};
  REQUIRE(run_mesh(c) == 0);
  const nlohmann::json run = read_quality_json(out / "quality.json")["boundary_layer"];
  {  // The run's own quality.json: its boundary_layer member follows cleanup's value on its line.
    const std::string json = read_text_file(out / "quality.json");
    INFO(json.substr(json.find("\"cleanup\"")));
    CHECK(json.find("  \"cleanup\": null,\n  \"boundary_layer\": {\n    \"tables\": [\n      {\"curves\"") !=
          std::string::npos);
    CHECK(json.find("\n,") == std::string::npos);
  }
  const Measured msh = measure(out / "mesh.msh"), vtu = measure(out / "mesh.vtu"), su2 = measure(out / "mesh.su2"),
                 medit = measure(out / "mesh.mesh");
  for (const Measured* m : {&msh, &vtu, &su2, &medit}) {
    INFO(m->text + m->err);
    CHECK(m->err.find("skipped") == std::string::npos);
    REQUIRE(m->q.contains("cells"));
    CHECK(m->q["cells"]["points"].get<long long>() == run["points"].get<long long>());
    CHECK(m->q["cells"]["all"]["cells"].get<long long>() == run["cells"].get<long long>());
    CHECK(m->q["cells"]["all"]["quads"].get<long long>() == run["quads"].get<long long>());
    check_same_cells(m->q["cells"]["all"], msh.q["cells"]["all"]);
    // The triangles' table is the same mesh's in every format.
    CHECK(m->q["triangles"] == msh.q["triangles"]);
    CHECK(m->q["included_angle"] == msh.q["included_angle"]);
    CHECK(m->q["histograms"] == msh.q["histograms"]);
  }
  // VTU names the layer by its cell data as MSH does by its group; SU2 cannot (no volume markers):
  // there every quad is a layer cell.
  CHECK(msh.q["cells"]["layer_cells"].get<std::string>() == "boundary_layer");
  CHECK(vtu.q["cells"]["layer_cells"].get<std::string>() == "boundary_layer");
  check_same_cells(vtu.q["cells"]["layer"], msh.q["cells"]["layer"]);
  CHECK(vtu.text.find("boundary layer (the file's \"boundary_layer\" cell data)") != std::string::npos);
  // Medit names it by a reference (its "# ref 1: region boundary_layer" comment).
  CHECK(medit.q["cells"]["layer_cells"].get<std::string>() == "boundary_layer");
  check_same_cells(medit.q["cells"]["layer"], msh.q["cells"]["layer"]);
  CHECK(medit.text.find("boundary layer (the file's \"boundary_layer\" reference)") != std::string::npos);
  CHECK(su2.q["cells"]["layer_cells"].get<std::string>() == "quads");
  CHECK(su2.q["cells"]["layer"]["quads"].get<long long>() == run["quads"].get<long long>());
  CHECK(su2.q["cells"]["layer"]["triangles"].get<long long>() == 0);
  CHECK(su2.text.find("quads (the format names no boundary layer)") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("quality of VTU and SU2 files with quads: counts, angles, a clockwise quad turned, the region",
          "[quality][vtu][su2]") {
  const fs::path dir = pdmesh_test::fresh_path("quality_formats_small");
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The MSH 2.2 test's cells: a unit square, a trapezoid (corners 90, 135, 45, 90 degrees) written
  // clockwise and a right triangle over the square; the two quads in "boundary_layer".
  const std::string points = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n3 1 0\n0 2 0\n";
  const auto vtu = [&](const std::string& region) {
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
           "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"7\" NumberOfCells=\"3\">\n"
           "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n" +
           points +
           "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n"
           "0 1 2 3\n3 2 6\n1 2 5 4\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n"
           "4 7 11\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n9 5 9\n</DataArray>\n"
           "</Cells>\n<CellData>\n<DataArray type=\"UInt8\" Name=\"" +
           region +
           "\" format=\"ascii\">\n1 0 1\n</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  };
  write_text_file(dir / "m.vtu", vtu("boundary_layer"));
  write_text_file(dir / "other.vtu", vtu("region"));
  write_text_file(dir / "m.su2",
                  "NDIME= 2\nNELEM= 3\n9 0 1 2 3 0\n5 3 2 6 1\n9 1 2 5 4 2\nNPOIN= 7\n0 0\n1 0\n1 1\n0 1\n2 0\n"
                  "3 1\n0 2\nNMARK= 1\nMARKER_TAG= bottom\nMARKER_ELEMS= 1\n3 0 1\n");
  for (const char* name : {"m.vtu", "other.vtu", "m.su2"}) {
    const Measured m = measure(dir / name);
    INFO(name << "\n" << m.text + m.err);
    CHECK(m.err.find("skipped") == std::string::npos);
    CHECK(m.err.find("turned 1 clockwise quadrangles counter-clockwise") != std::string::npos);
    const nlohmann::json& q = m.q["cells"];
    CHECK(q["points"].get<int>() == 7);
    CHECK(q["all"]["cells"].get<int>() == 3);
    CHECK(q["all"]["quads"].get<int>() == 2);
    CHECK(q["all"]["triangles"].get<int>() == 1);
    CHECK(q["all"]["inverted_cells"].get<int>() == 0);
    CHECK(q["all"]["max_angle"].get<double>() == Approx(135.0).epsilon(1e-12));
    CHECK(q["layer_cells"].get<std::string>() == (std::string(name) == "m.vtu" ? "boundary_layer" : "quads"));
    CHECK(q["layer"]["cells"].get<int>() == 2);
    CHECK(q["layer"]["quads"].get<int>() == 2);
    CHECK(q["layer"]["max_angle"].get<double>() == Approx(135.0).epsilon(1e-12));
    CHECK(m.q["triangles"].get<int>() == 1);
  }
  // A region flag other than 0 or 1 is refused, naming the file, the array and the cell.
  std::string bad = vtu("boundary_layer");
  bad.replace(bad.find("1 0 1\n"), 6, "1 0 2\n");
  write_text_file(dir / "bad.vtu", bad);
  std::ostringstream text, err;
  CHECK_THROWS_WITH(run_quality((dir / "bad.vtu").string(), std::nullopt, std::nullopt, text, err),
                    Catch::Contains("bad.vtu") && Catch::Contains("'boundary_layer' holds 2 at cell 2"));
  fs::remove_all(dir);
}
