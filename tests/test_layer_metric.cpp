// Boundary layers under a metric field (docs/boundary-layers.md, "Under a metric field"): the core
// is measured in the case's metric, and the layer's front follows the metric (wall nodes at about
// unit metric length along the wall, the thickness stopped by the metric's length along the rays).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;

namespace {

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

double json_number(const std::string& json, const std::string& key) {
  std::smatch m;
  REQUIRE(std::regex_search(json, m, std::regex("\"" + key + "\": ([-0-9.eE+]+)")));
  return std::stod(m[1]);
}

// A flat plate [0, 1] x [-0.01, 0.01] (one closed curve "plate", its long sides with a point every
// 0.005) inside a box "outer" [-0.5, 1.5] x [-0.3, 0.3], as a curve file.
void write_plate(const fs::path& file) {
  std::ofstream out(file);
  const int n = 200;
  out << 2 * (n + 1) + 1 << "\n";
  for (int i = 0; i <= n; ++i) out << 0.005 * i << " -0.01\n";
  for (int i = n; i >= 0; --i) out << 0.005 * i << " 0.01\n";
  out << "0 -0.01\n";
  out << "5\n-0.5 -0.3\n1.5 -0.3\n1.5 0.3\n-0.5 0.3\n-0.5 -0.3\n";
}

// The plate's layer (h1 1e-4, growth 1.2, thickness 0.1, triangles) under `spacing`.
std::string plate_case(const fs::path& crv, const std::string& spacing) {
  return "[geometry]\nfiles = [\"" + crv.string() +
         "\"]\ncurve_names = [\"plate\", \"outer\"]\n"
         "[simulation]\ndevice = \"host\"\n[output]\nformats = [\"msh\"]\n" +
         spacing +
         "[[boundary_layer]]\ncurves = [\"plate\"]\nfirst_height = 1e-4\ngrowth = 1.2\nthickness = 0.1\n"
         "elements = \"triangles\"\n";
}

}  // namespace

TEST_CASE("a flat plate's layer under a constant anisotropic metric: the front in the metric's window",
          "[app][layers][metric]") {
  // M = diag(1/0.1^2, 1/0.01^2): unit length is 0.1 along the plate and 0.01 across it. The input's
  // wall points are 0.005 apart (metric length 0.05 along the plate); the front's edges follow the
  // metric along the wall, and the layers stop where growth x their height reaches 0.01 (their
  // length along the ray is 1), so that the last layer is about 1 / growth in the metric.
  const fs::path out = fs::temp_directory_path() / "pdmesh_test_layer_metric";
  fs::remove_all(out);
  fs::create_directories(out);
  write_plate(out / "plate.crv");
  CaseConfig c = parse_case_text(
      plate_case(out / "plate.crv", "[spacing]\nfield = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.01\"\nangle = \"0\"\n"),
      out / "case.toml");
  c.out_dir = out / "run";
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const std::string json = read(out / "run" / "quality.json");
  // The core's measures in the metric, as a metric run without layers reports them.
  const std::size_t metric = json.find("\"metric\": {");
  REQUIRE(metric != std::string::npos);
  CHECK(json_number(json.substr(metric), "window_percent") >= 90.0);
  CHECK(json_number(json.substr(metric), "q_mean") >= 0.8);
  // No isotropic min angle for the anisotropic core.
  CHECK(json.find("\"core_min_angle\": null") != std::string::npos);
  // The fronts in the metric.
  const std::size_t front = json.find("\"front_in_metric\"");
  REQUIRE(front != std::string::npos);
  const std::string f = json.substr(front);
  // The sides' front edges are at unit length (the input's wall points at 0.05), none is longer than
  // the window; the corners' fans (elements of equal angle, most of the front's edges) have edges
  // down to 0.1 where they turn along the plate, so the median and the share in the window are lower.
  CHECK(json_number(f, "length_max") <= std::sqrt(2.0));
  CHECK(json_number(f, "length_median") >= 0.5);
  CHECK(json_number(f, "window_percent") >= 40.0);
  CHECK(json_number(f, "last_layer_median") >= 0.6);
  CHECK(json_number(f, "last_layer_median") <= 1.0);
  // The layer itself as without a metric: the first height exact, nothing inverted.
  CHECK(json_number(json, "first_height_within_2pct") == 1.0);
  CHECK(json_number(json, "inverted_cells") == 0.0);
  fs::remove_all(out);
}

TEST_CASE("the same plate without a metric keeps the input's wall points and reports no metric", "[app][layers]") {
  const fs::path out = fs::temp_directory_path() / "pdmesh_test_layer_metric_iso";
  fs::remove_all(out);
  fs::create_directories(out);
  write_plate(out / "plate.crv");
  CaseConfig c = parse_case_text(plate_case(out / "plate.crv", "[spacing]\nsize = 0.02\n"), out / "case.toml");
  c.out_dir = out / "run";
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const std::string json = read(out / "run" / "quality.json");
  CHECK(json.find("\"metric\"") == std::string::npos);
  CHECK(json.find("\"front_in_metric\"") == std::string::npos);
  CHECK(json_number(json, "core_min_angle") > 20.0);
  // Every input point of the plate is a wall node: 402 wall cells (400 along the sides, 2 at the ends).
  CHECK(json_number(json, "wall_cells") >= 402.0);
  fs::remove_all(out);
}
