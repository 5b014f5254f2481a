// The best preset's simulation.stop_angle per kind of run: 6 degrees for an isotropic run, 3 for a
// metric one (docs/simulation.md, "When a run stops"), and a value the case sets wins in both, from
// the file, --set or the Python API's settings (case_for_curves' overrides).
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "case_texts.hpp"

using namespace pdmesh;
using namespace pdmesh_test;
namespace fs = std::filesystem;

namespace {

const fs::path kAnisoLinear = fs::path(PDMESH_SOURCE_DIR) / "cases" / "aniso" / "linear" / "case.toml";
const fs::path kCircles = fs::path(PDMESH_SOURCE_DIR) / "cases" / "circle_circle" / "circles.crv";

double stop_angle(const std::string& text, const std::vector<CaseOverride>& overrides = {}) {
  return parse_case_text(text, kCase, overrides).simulation.stop_angle;
}

std::vector<RawCurve> unit_square() {
  return {RawCurve{"box", {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}, "memory", 1, {}}};
}

}  // namespace

TEST_CASE("stop_angle: best's is 6 degrees for an isotropic run and 3 for a metric one, the others' 0.25",
          "[app][case][convergence]") {
  CHECK(preset_stop_angle(Preset::Best, false) == 6.0);
  CHECK(preset_stop_angle(Preset::Best, true) == 3.0);
  CHECK(preset_stop_angle(Preset::Fast, false) == 6.0);
  CHECK(preset_stop_angle(Preset::Fast, true) == 3.0);
  for (bool metric : {false, true}) {
    CHECK(preset_stop_angle(Preset::Thesis, metric) == 0.25);
    CHECK(preset_stop_angle(Preset::Long, metric) == 0.25);
  }

  // Parsed: the kind of run decides where the file leaves the key out.
  CHECK(stop_angle(kGeometry) == 6.0);
  CHECK(stop_angle("preset = \"fast\"\n" + kGeometry) == 6.0);
  CHECK(stop_angle(kGeometry + kMetric) == 3.0);
  CHECK(stop_angle(kGeometry + kHessian) == 3.0);
  CHECK(stop_angle(kGeometry + "[spacing]\nfield = \"expression\"\nexpression = \"0.1\"\n") == 6.0);
  CHECK(stop_angle("preset = \"thesis\"\n" + kGeometry + kMetric) == 0.25);
  CHECK(stop_angle("preset = \"long\"\n" + kGeometry) == 0.25);
  CHECK(load_case_file(kAnisoLinear).simulation.stop_angle == 3.0);
  CHECK(case_for_geometry_files({kCircles}).simulation.stop_angle == 6.0);
  CHECK(case_for_curves(unit_square(), "square").simulation.stop_angle == 6.0);
  // A run made metric by --set takes the metric value too.
  CHECK(stop_angle(kGeometry, {parse_set_option("spacing.field=metric"), parse_set_option("spacing.h1=\"0.1\""),
                               parse_set_option("spacing.h2=\"0.01\"")}) == 3.0);

  // The convergence rule gets it.
  CHECK(simulation_options(parse_case_text(kGeometry, kCase)).convergence.angle_tolerance == 6.0);
  CHECK(simulation_options(load_case_file(kAnisoLinear)).convergence.angle_tolerance == 3.0);

  // apply_preset on a CaseConfig built in code looks at its field as it is then.
  CaseConfig by_hand;
  by_hand.spacing.field = SpacingKind::Metric;
  apply_preset(by_hand, Preset::Best);
  CHECK(by_hand.simulation.stop_angle == 3.0);
  apply_preset(by_hand, Preset::Long);
  CHECK(by_hand.simulation.stop_angle == 0.25);
  by_hand.spacing.field = SpacingKind::Boundary;
  apply_preset(by_hand, Preset::Best);
  CHECK(by_hand.simulation.stop_angle == 6.0);
}

TEST_CASE("stop_angle: a value the case sets wins over the preset's in both kinds of run", "[app][case][convergence]") {
  for (const char* value : {"3", "6", "0.5"}) {
    INFO("stop_angle " << value);
    const double v = std::stod(value);
    const std::string key = std::string("[simulation]\nstop_angle = ") + value + "\n";
    const CaseOverride set = parse_set_option(std::string("simulation.stop_angle=") + value);
    // In the file.
    CHECK(stop_angle(kGeometry + key) == v);
    CHECK(stop_angle(kGeometry + kMetric + key) == v);
    CHECK(stop_angle(kGeometry + kHessian + key) == v);
    CHECK(stop_angle("preset = \"thesis\"\n" + kGeometry + kMetric + key) == v);
    // By --set, in either order with the key that makes the run metric.
    CHECK(stop_angle(kGeometry, {set}) == v);
    CHECK(stop_angle(kGeometry + kMetric, {set}) == v);
    CHECK(load_case_file(kAnisoLinear, {set}).simulation.stop_angle == v);
    CHECK(stop_angle(kGeometry, {set, parse_set_option("spacing.field=metric"), parse_set_option("spacing.h1=\"0.1\""),
                                 parse_set_option("spacing.h2=\"0.01\"")}) == v);
    CHECK(case_for_geometry_files({kCircles}, {set}).simulation.stop_angle == v);
    // The Python API's settings= reach the core as these overrides.
    CHECK(case_for_curves(unit_square(), "square", {set}).simulation.stop_angle == v);
    CHECK(simulation_options(load_case_file(kAnisoLinear, {set})).convergence.angle_tolerance == v);
  }
  // A metric file made isotropic by --set (its metric keys left out) takes the isotropic value, and an
  // isotropic file made metric the metric one: the kind the case ends up with decides.
  const std::string metric_field = "[spacing]\nfield = \"metric\"\n";
  CHECK(stop_angle(kGeometry + metric_field, {parse_set_option("spacing.field=boundary")}) == 6.0);
  CHECK(stop_angle(kGeometry + "[spacing]\nfield = \"boundary\"\n",
                   {parse_set_option("spacing.field=metric"), parse_set_option("spacing.h1=\"0.1\""),
                    parse_set_option("spacing.h2=\"0.01\"")}) == 3.0);
}
