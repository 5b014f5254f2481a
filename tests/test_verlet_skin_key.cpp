// simulation.verlet_skin: "auto" (the default) picks the skin by momentum and node count
// (auto_verlet_skin); a number in [0, 4] is the run's skin at every size; anything else is refused
// naming the key. The skin never changes a result (the device run tests compare skins), so what is
// tested here is which skin reaches SimOptions.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "sim/verlet_skin.hpp"
#include "case_texts.hpp"
#include "run_pdmesh.hpp"
#include "source_dir.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using namespace pdmesh_test;

namespace {

CaseConfig parsed(const std::string& text, const std::vector<CaseOverride>& overrides = {}) {
  return parse_case_text(text, kCase, overrides);
}

}  // namespace

TEST_CASE("simulation.verlet_skin: auto by default, a number, and errors naming the key", "[app][case]") {
  CHECK_FALSE(parsed(kGeometry).simulation.verlet_skin.has_value());
  CHECK_FALSE(parsed(kGeometry + "[simulation]\nverlet_skin = \"auto\"\n").simulation.verlet_skin.has_value());
  CHECK(parsed(kGeometry + "[simulation]\nverlet_skin = 0.65\n").simulation.verlet_skin == 0.65);
  CHECK(parsed(kGeometry + "[simulation]\nverlet_skin = 0\n").simulation.verlet_skin == 0.0);
  CHECK(parsed(kGeometry, {parse_set_option("simulation.verlet_skin=0.8")}).simulation.verlet_skin == 0.8);
  CHECK_FALSE(parsed(kGeometry + "[simulation]\nverlet_skin = 0.8\n", {parse_set_option("simulation.verlet_skin=auto")})
                  .simulation.verlet_skin.has_value());
  for (const char* bad : {"-0.1", "4.5", "\"big\""})
    CHECK_THROWS_WITH(parsed(kGeometry + "[simulation]\nverlet_skin = " + bad + "\n"),
                      Catch::Contains("simulation.verlet_skin must be a number in [0, 4] or \"auto\""));
  for (const char* bad : {"true", "nan"})
    CHECK_THROWS_WITH(parsed(kGeometry + "[simulation]\nverlet_skin = " + bad + "\n"),
                      Catch::Contains("simulation.verlet_skin"));
}

TEST_CASE("auto_verlet_skin: the thesis' skin without momentum, by node count with it", "[app][case]") {
  for (std::size_t n : {std::size_t{0}, kSmallRunNodes, std::size_t{20'000'000}})
    CHECK(auto_verlet_skin(0.0, n) == kVerletSkin);
  CHECK(auto_verlet_skin(0.9, 0) == kSmallRunVerletSkin);
  CHECK(auto_verlet_skin(0.9, kSmallRunNodes - 1) == kSmallRunVerletSkin);
  CHECK(auto_verlet_skin(0.9, kSmallRunNodes) == kMomentumVerletSkin);
  CHECK(auto_verlet_skin(0.9, 20'000'000) == kMomentumVerletSkin);
  // The small runs' skin differs from the large ones' (else the rule would not depend on size), and
  // every automatic skin is a valid value of the key.
  CHECK(kSmallRunVerletSkin != kMomentumVerletSkin);
  for (double s : {kVerletSkin, kSmallRunVerletSkin, kMomentumVerletSkin}) {
    CHECK(s > 0.0);
    CHECK(s <= 4.0);
  }
}

TEST_CASE("simulation_options: the case's skin at every size, else the automatic one for the node count",
          "[app][case]") {
  const CaseConfig best = parsed(kGeometry);
  REQUIRE(best.simulation.momentum > 0.0);
  for (std::size_t n : {std::size_t{14'000}, std::size_t{265'000}, std::size_t{5'300'000}})
    CHECK(simulation_options(best, n).verlet_skin == auto_verlet_skin(best.simulation.momentum, n));
  CHECK(simulation_options(best).verlet_skin == auto_verlet_skin(best.simulation.momentum, 0));
  const CaseConfig thesis = parsed("preset = \"thesis\"\n" + kGeometry);
  CHECK(simulation_options(thesis, 5'300'000).verlet_skin == kVerletSkin);
  const CaseConfig fixed = parsed(kGeometry, {parse_set_option("simulation.verlet_skin=0.7")});
  for (std::size_t n : {std::size_t{14'000}, std::size_t{265'000}, std::size_t{5'300'000}})
    CHECK(simulation_options(fixed, n).verlet_skin == 0.7);
}

// pdmesh bench without --skin takes a case file's simulation.verlet_skin: at 0 the device run rebuilds
// its lists every iteration, where the circle_circle case's automatic skin lasts several.
TEST_CASE("pdmesh bench takes the case file's simulation.verlet_skin", "[app][bench]") {
  namespace fs = std::filesystem;
  const fs::path dir = pdmesh_test::fresh_dir("bench_case_skin");
  const fs::path source = fs::path(pdmesh::test::source_dir()) / "cases" / "circle_circle";
  for (const char* name : {"automatic", "zero"}) fs::copy(source, dir / name, fs::copy_options::recursive);
  {
    std::string text = pdmesh_test::slurp(dir / "zero" / "case.toml");
    const std::size_t at = text.find("[simulation]\n");
    REQUIRE(at != std::string::npos);
    text.insert(at + 13, "verlet_skin = 0\n");
    std::ofstream(dir / "zero" / "case.toml") << text;
  }
  const auto rebuilds = [&](const char* name) {
    const auto r = pdmesh_test::run_pdmesh("bench --cases " + std::string(name) + " --cases-dir '" + dir.string() +
                                           "' --warmup 0 --iterations 8 --skip-host");
    INFO(r.output);
    REQUIRE(r.status == 0);
    std::smatch m;  // the first table row's device split: "(N rebuilds, ..."
    REQUIRE(std::regex_search(r.output, m, std::regex("\\((\\d+) rebuilds,")));
    return std::stoi(m[1].str());
  };
  CHECK(rebuilds("zero") == 8);
  CHECK(rebuilds("automatic") < 8);
  fs::remove_all(dir);
}
