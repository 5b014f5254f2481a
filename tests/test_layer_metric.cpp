// Boundary layers under a metric field (docs/boundary-layers.md, "Under a metric field"): the core
// is measured in the metric, the layer's front follows the metric (wall nodes at about unit metric
// length along the wall, the thickness stopped by the metric's length along the rays), and a layer
// thinner than the metric across the wall meets a core whose metric is graded down to it.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/layer_pipeline.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "quality_json.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using pdmesh_test::read_quality_json;

namespace {

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

// The plate's layer (h1 1e-4, growth 1.2, `thickness`, triangles) under `spacing`.
std::string plate_case(const fs::path& crv, const std::string& spacing, const std::string& thickness = "0.1") {
  return "[geometry]\nfiles = [\"" + crv.string() +
         "\"]\ncurve_names = [\"plate\", \"outer\"]\n"
         "[simulation]\ndevice = \"host\"\n[output]\nformats = [\"msh\"]\n" +
         spacing +
         "[[boundary_layer]]\ncurves = [\"plate\"]\nfirst_height = 1e-4\ngrowth = 1.2\nthickness = " + thickness +
         "\nelements = \"triangles\"\n";
}

const std::string kPlateMetric = "[spacing]\nfield = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.01\"\nangle = \"0\"\n";

}  // namespace

TEST_CASE("a flat plate's layer under a constant anisotropic metric: the front in the metric's window",
          "[app][layers][metric]") {
  // M = diag(1/0.1^2, 1/0.01^2): unit length is 0.1 along the plate and 0.01 across it. The input's
  // wall points are 0.005 apart (metric length 0.05 along the plate); the front's edges follow the
  // metric along the wall, and the layers stop where growth x their height reaches 0.01 (their
  // length along the ray is 1), so that the last layer is about 1 / growth in the metric.
  const fs::path out = pdmesh_test::fresh_path("layer_metric");
  fs::remove_all(out);
  fs::create_directories(out);
  write_plate(out / "plate.crv");
  CaseConfig c = parse_case_text(plate_case(out / "plate.crv", kPlateMetric), out / "case.toml");
  c.out_dir = out / "run";
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const nlohmann::json q = read_quality_json(out / "run" / "quality.json");
  // The core's measures in the metric, as a metric run without layers reports them.
  REQUIRE(q.contains("metric"));
  CHECK(q["metric"]["window_percent"].get<double>() >= 90.0);
  CHECK(q["metric"]["q_mean"].get<double>() >= 0.8);
  // No isotropic min angle for the anisotropic core.
  const nlohmann::json& layer = q["boundary_layer"];
  CHECK(layer["core_min_angle"].is_null());
  // The fronts in the metric.
  REQUIRE(layer.contains("front_in_metric"));
  const nlohmann::json& f = layer["front_in_metric"];
  // The sides' front edges are at unit length (the input's wall points at 0.05), none is longer than
  // the window; the corners' fans (elements of equal angle, most of the front's edges) have edges
  // down to 0.1 where they turn along the plate, so the median and the share in the window are lower.
  CHECK(f["length_max"].get<double>() <= std::sqrt(2.0));
  CHECK(f["length_median"].get<double>() >= 0.5);
  CHECK(f["window_percent"].get<double>() >= 40.0);
  CHECK(f["last_layer_median"].get<double>() >= 0.6);
  CHECK(f["last_layer_median"].get<double>() <= 1.0);
  // The layer itself as without a metric: the first height exact, nothing inverted.
  CHECK(layer["tables"][0]["first_height_within_2pct"].get<double>() == 1.0);
  CHECK(layer["tables"][0]["inverted_cells"].get<int>() == 0);
  fs::remove_all(out);
}

TEST_CASE("a layer thinner than the metric across the wall meets a core graded down to it", "[app][layers][metric]") {
  // The same plate and metric with a thickness of 0.002: the layer ends (about 9 layers, the last
  // about 4.3e-4) far below the metric's 0.01 across the wall, at about 0.05 metric units. The core's
  // metric is graded from growth x the last layer at the front, so the core triangle on a front edge
  // is about as high as the next layer would be: the junction (both heights in the case's metric)
  // near growth, not the metric's 0.01 over the last layer (about 20). The core is measured in the
  // graded metric it was meshed in.
  const fs::path out = pdmesh_test::fresh_path("layer_metric_thin");
  fs::remove_all(out);
  fs::create_directories(out);
  write_plate(out / "plate.crv");
  CaseConfig c = parse_case_text(plate_case(out / "plate.crv", kPlateMetric, "0.002"), out / "case.toml");
  c.out_dir = out / "run";
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const nlohmann::json q = read_quality_json(out / "run" / "quality.json");
  const nlohmann::json& layer = q["boundary_layer"];
  // The layer as given: its thickness not stopped by the metric, its last layer far below one unit.
  CHECK(layer["tables"][0]["max_thickness"].get<double>() <= 0.0021);
  CHECK(layer["front_in_metric"]["last_layer_median"].get<double>() <= 0.1);
  // The step from the last layer into the core.
  const double junction = layer["junction"]["median"].get<double>();
  CHECK(junction >= 0.5);
  CHECK(junction <= 2.0);
  CHECK(layer["junction"]["p95"].get<double>() <= 4.0);
  // The core follows its graded metric as well as a core in the plain metric does.
  REQUIRE(q.contains("metric"));
  CHECK(q["metric"]["window_percent"].get<double>() >= 90.0);
  CHECK(q["metric"]["q_mean"].get<double>() >= 0.8);
  CHECK(layer["tables"][0]["first_height_within_2pct"].get<double>() == 1.0);
  CHECK(layer["tables"][0]["inverted_cells"].get<int>() == 0);
  fs::remove_all(out);
}

TEST_CASE("a layer cut by a facing wall meets a core graded down to it as a full one does", "[app][layers][metric]") {
  // Two plates 0.0045 apart under the plate's metric (0.01 across the wall), layers of 0.002: the
  // facing sides' rays see the other plate within their thickness over gap_fraction and stop at
  // 0.4 of the gap (0.0018), their last layers about 0.03 metric units. The metric stops no ray.
  // A ray cut so is as far below the metric's unit as a full one: its top is a source of the core's
  // graded metric too (a slot's core is not sized by the metric's 0.01 across it).
  const fs::path out = pdmesh_test::fresh_path("layer_metric_slot");
  fs::remove_all(out);
  fs::create_directories(out);
  {
    std::ofstream crv(out / "plates.crv");
    const int n = 200;
    for (const double y0 : {-0.01, 0.0145}) {
      crv << 2 * (n + 1) + 1 << "\n";
      for (int i = 0; i <= n; ++i) crv << 0.005 * i << " " << y0 << "\n";
      for (int i = n; i >= 0; --i) crv << 0.005 * i << " " << y0 + 0.02 << "\n";
      crv << "0 " << y0 << "\n";
    }
    crv << "5\n-0.5 -0.3\n1.5 -0.3\n1.5 0.3\n-0.5 0.3\n-0.5 -0.3\n";
  }
  const std::string text = "[geometry]\nfiles = [\"" + (out / "plates.crv").string() +
                           "\"]\ncurve_names = [\"lower\", \"upper\", \"outer\"]\n"
                           "[simulation]\ndevice = \"host\"\n[output]\nformats = [\"msh\"]\n" +
                           kPlateMetric +
                           "[[boundary_layer]]\ncurves = [\"lower\", \"upper\"]\nfirst_height = 1e-4\ngrowth = "
                           "1.2\nthickness = 0.002\nelements = \"triangles\"\n";
  const CaseConfig c = parse_case_text(text, out / "case.toml");
  const MeshInputs inputs(c);
  const SpacingStage spacing(c, inputs);
  const auto layered = build_layers(c, inputs, spacing);
  const LayerMesh& m = layered->sections.at(0).mesh;
  std::size_t cut = 0, tops = 0;
  for (const LayerRay& ray : m.rays) {
    CHECK(ray.free_thickness >= 0.99 * 0.002);  // the metric stops none
    if (ray.merged || ray.nodes.size() < 2) continue;
    ++tops;
    if (ray.thickness < 0.99 * 0.002) ++cut;
  }
  CHECK(cut >= 10);  // the facing sides (wall nodes about 0.1 apart: a metric unit along the wall)
  // Every top is a source: the cut ones as the full ones.
  CHECK(layered->front_metric.size() == tops);
  fs::remove_all(out);
}

TEST_CASE("the same plate without a metric keeps the input's wall points and reports no metric", "[app][layers]") {
  const fs::path out = pdmesh_test::fresh_path("layer_metric_iso");
  fs::remove_all(out);
  fs::create_directories(out);
  write_plate(out / "plate.crv");
  CaseConfig c = parse_case_text(plate_case(out / "plate.crv", "[spacing]\nsize = 0.02\n"), out / "case.toml");
  c.out_dir = out / "run";
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const nlohmann::json q = read_quality_json(out / "run" / "quality.json");
  CHECK_FALSE(q.contains("metric"));
  CHECK_FALSE(q["boundary_layer"].contains("front_in_metric"));
  CHECK(q["boundary_layer"]["core_min_angle"].get<double>() > 20.0);
  // Every input point of the plate is a wall node: 402 wall cells (400 along the sides, 2 at the ends).
  CHECK(q["boundary_layer"]["tables"][0]["wall_cells"].get<int>() >= 402);
  fs::remove_all(out);
}
