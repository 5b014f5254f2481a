// Whole runs (host, default preset) of geometries with a narrow gap beside long input segments: the
// feature size resolves the gap, so the meshes reach Triangle -q30's bound. Triangle's face.poly (the
// mouth 8.9 from the outer boundary along segments 89-112 long), a gap 0.05 wide above the unit
// square's bottom beside a 0.8 constraint segment or a 0.8 x 0.45 hole, and a strait 0.1 wide between
// two sides of one loop 10 long that connect only around a square (docs/spacing.md, "Feature size"
// and "Input boundary points"). Label `cases` (whole-case runs).
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace {

double min_angle(const std::string& quality_json) {
  const auto at = quality_json.find("\"included_angle\"");
  REQUIRE(at != std::string::npos);
  const auto min = quality_json.find("\"min\":", at);
  REQUIRE(min != std::string::npos);
  return std::strtod(quality_json.c_str() + min + 6, nullptr);
}

}  // namespace

TEST_CASE("a narrow gap beside long segments meshes with angles of 30 degrees or more", "[gap]") {
  const std::string source(PDMESH_SOURCE_DIR);
  const auto dir = pdmesh_test::fresh_dir("gap_field");
  for (const std::string& input : {source + "/cases/user_corpus/face", source + "/tests/data/gap/constraint_gap.poly",
                                   source + "/tests/data/gap/hole_gap.poly", source + "/tests/data/gap/strait.poly"}) {
    INFO(input);
    const auto out = dir / std::filesystem::path(input).stem();
    const auto r = pdmesh_test::run_pdmesh("mesh '" + input + "' --out '" + out.string() +
                                           "' --formats msh --device host --check -q");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(min_angle(pdmesh_test::slurp(out / "quality.json")) >= 30.0);
  }
  std::filesystem::remove_all(dir);
}
