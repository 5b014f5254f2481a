// The generated benchmark case annulus_<N> (app/bench/annulus_case) and the whole-run benchmark that uses it
// (app/bench/whole_run_bench): names, the geometry, the case files it writes (readable by the mesh command,
// whose node estimate comes out near N with the thesis' field), and one small `pdmesh bench
// --whole-run` whose tables and timings files are checked.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "app/bench/annulus_case.hpp"
#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/bench/whole_run_bench.hpp"
#include "io/text_file.hpp"
#include "json_check.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;

TEST_CASE("annulus case: names give the node target", "[bench][annulus]") {
  CHECK(annulus_target("annulus_4m") == 4'000'000u);
  CHECK(annulus_target("annulus_250k") == 250'000u);
  CHECK(annulus_target("annulus_1200") == 1200u);
  for (const char* other : {"annulus_0", "annulus_", "annulus_4M", "annulus_4g", "annulus_-3", "xannulus_5",
                            "annulus_5 ", "30p30n", "annulus_1m/case.toml"}) {
    INFO(other);
    CHECK_FALSE(annulus_target(other));
  }
}

TEST_CASE("annulus case: two closed circles, boundary segments 20x longer outside, sized by the estimate",
          "[bench][annulus]") {
  for (const std::size_t target : {std::size_t{2000}, std::size_t{1'000'000}}) {
    INFO("target " << target);
    const double h = annulus_inner_spacing(target);
    CHECK(annulus_node_estimate(h) == Approx(static_cast<double>(target)).epsilon(1e-12));
    // Four times the nodes: half the spacing.
    CHECK(annulus_inner_spacing(4 * target) == Approx(h / 2).epsilon(1e-12));
    const std::vector<RawCurve> curves = annulus_curves(target);
    REQUIRE(curves.size() == 2);
    CHECK(curves[0].name == "inner");
    CHECK(curves[1].name == "outer");
    for (std::size_t c = 0; c < 2; ++c) {
      const RawCurve& curve = curves[c];
      const double radius = c == 0 ? kAnnulusInnerRadius : kAnnulusOuterRadius;
      REQUIRE(curve.points.size() >= 9);
      CHECK(curve.points.front().x == curve.points.back().x);  // closed
      CHECK(curve.points.front().y == curve.points.back().y);
      for (const Vec2& p : curve.points) CHECK(std::hypot(p.x, p.y) == Approx(radius).epsilon(1e-12));
    }
    const double inner = 2 * std::numbers::pi * kAnnulusInnerRadius / static_cast<double>(curves[0].points.size() - 1);
    const double outer = 2 * std::numbers::pi * kAnnulusOuterRadius / static_cast<double>(curves[1].points.size() - 1);
    CHECK(inner == Approx(h).epsilon(0.05));
    CHECK(outer / inner == Approx(kAnnulusSpacingRatio).epsilon(0.1));
  }
}

TEST_CASE("annulus case: the written case is read by the mesh command's stages, its estimate near N",
          "[bench][annulus]") {
  const fs::path dir = pdmesh_test::fresh_dir("annulus_case");
  // whole_run_inputs generates annulus_<N> into WORK/cases/annulus_<N>/.
  const std::vector<std::string> inputs = whole_run_inputs("annulus_3000", "cases", dir.string());
  REQUIRE(inputs.size() == 1);
  const fs::path case_file = inputs[0];
  CHECK(case_file == dir / "cases" / "annulus_3000" / "case.toml");
  REQUIRE(fs::is_regular_file(dir / "cases" / "annulus_3000" / "inner.crv"));
  REQUIRE(fs::is_regular_file(dir / "cases" / "annulus_3000" / "outer.crv"));
  // Eq. 3.6 (the thesis preset) is the field the target was computed for.
  CaseConfig config = load_case_file(case_file, {{"preset", "thesis", "test"}});
  CHECK(config.name == "annulus_3000");
  config.quiet = true;
  const MeshInputs thesis(config);
  REQUIRE(thesis.geometry.curves.size() == 2);
  CHECK(thesis.geometry.curves[0].name == "inner");
  CHECK(thesis.geometry.area == Approx(std::numbers::pi * (100.0 - 1.0)).epsilon(0.01));
  CHECK(check_node_limit(config, thesis, SpacingStage(config, thesis)) == Approx(3000.0).epsilon(0.05));
  // The case itself names no preset: the best one, whose gradation and curvature limits add nodes and
  // whose spacing.relax_scale c relaxes the nodes at c q: 1/c^2 of them (measured 2516 at c = 1.09).
  CaseConfig best = load_case_file(case_file);
  best.quiet = true;
  const MeshInputs best_inputs(best);
  const double estimate = check_node_limit(best, best_inputs, SpacingStage(best, best_inputs));
  const double relaxed = 3000.0 / (best.spacing.relax_scale * best.spacing.relax_scale);
  CHECK(estimate >= relaxed * 0.95);
  CHECK(estimate <= relaxed * 3.0);
  // A name that is no annulus is passed through: a case directory, or paths joined with '+'.
  CHECK(whole_run_inputs("a.crv+b.crv", "cases", dir.string()) == std::vector<std::string>{"a.crv", "b.crv"});
  fs::remove_all(dir);
}

TEST_CASE("bench --whole-run: repeated runs of a generated case, every phase with min / median / max",
          "[bench][annulus][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("whole_run_bench");
  const pdmesh_test::Result r = pdmesh_test::run_pdmesh(
      "bench --whole-run --cases annulus_1500 --repeat 2 --backends host --set simulation.iterations=5 --work-dir '" +
      dir.string() + "' --out '" + (dir / "table.md").string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const std::string table = read_text_file(dir / "table.md");
  CHECK(table.find("| annulus_1500 | host |") != std::string::npos);
  CHECK(table.find("#### annulus_1500 on host") != std::string::npos);
  for (const char* phase :
       {"| read |", "| spacing |", "| estimate |", "| fill |", "| simulation |", "| triangulation |", "| mesh msh |",
        "| pictures (background thread", "| **whole process** |"})
    CHECK(table.find(phase) != std::string::npos);
  CHECK(table.find("min / median / max") != std::string::npos);
  // Each run a process of its own with its timings file (valid JSON); pictures kept by default.
  for (const char* run : {"run1", "run2"}) {
    const fs::path out = dir / "annulus_1500_host" / run;
    REQUIRE(fs::is_regular_file(out / "timings.json"));
    pdmesh_test::JsonCheck check;
    CHECK(check.valid(read_text_file(out / "timings.json")));
    CHECK(fs::is_regular_file(out / "mesh.png"));
    CHECK(fs::is_regular_file(out / "mesh.msh"));
  }
  // A failing run fails the bench (exit 1), and --repeat 0 is refused (exit 2).
  const pdmesh_test::Result bad =
      pdmesh_test::run_pdmesh("bench --whole-run --cases annulus_1500 --repeat 0 --work-dir '" + dir.string() + "'");
  CHECK(bad.status == 2);
  const pdmesh_test::Result failing = pdmesh_test::run_pdmesh(
      "bench --whole-run --cases annulus_1500 --repeat 1 --backends host --set simulation.iterations=-1 --work-dir '" +
      dir.string() + "'");
  CHECK(failing.status == 1);
  fs::remove_all(dir);
}

TEST_CASE("bench --whole-run: a device-resident run's floor is its device's and the host reference's the CPU's",
          "[bench][annulus][cli][opencl]") {
  const fs::path dir = pdmesh_test::fresh_dir("whole_run_bench_floor");
  const pdmesh_test::Result r = pdmesh_test::run_pdmesh(
      "bench --whole-run --cases annulus_1500 --repeat 1 --backends host opencl --no-pictures --floor-repeat 1 "
      "--set simulation.iterations=5 --work-dir '" +
      dir.string() + "' --out '" + (dir / "table.md").string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const std::string table = read_text_file(dir / "table.md");
  INFO(table);
  // The summary rows' floor cells (the second last cell): "S / V; CPU C" for the host, "device T; CPU C"
  // for PoCL's CPU device.
  const auto floor_cell = [&](const std::string& backend) {
    const std::size_t row = table.find("| annulus_1500 | " + backend + " |");
    REQUIRE(row != std::string::npos);
    const std::string line = table.substr(row, table.find('\n', row) - row);
    const std::size_t last = line.rfind(" | ", line.size() - 3);
    const std::size_t before = line.rfind(" | ", last - 1);
    return line.substr(before + 3, last - before - 3);
  };
  CHECK(floor_cell("host").find(" / ") != std::string::npos);
  CHECK(floor_cell("host").rfind("device ", 0) == std::string::npos);
  CHECK(floor_cell("opencl").rfind("device ", 0) == 0);
  CHECK(floor_cell("opencl").find("; CPU ") != std::string::npos);
  fs::remove_all(dir);
}
