// The best preset's drift tolerance, momentum steering, population control's stop and the structured
// start's step per kind of run: 1.5e-3, 0.2, 0.15 and 0.016 for an isotropic run, 7e-4, 0, 0.15 and the
// automatic rule for a metric one (docs/simulation.md, "When a run stops"); a value the case sets wins in
// both; pdmesh smooth keeps 7e-4, no steering and 0.2.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/smooth_pipeline.hpp"
#include "case_texts.hpp"

using namespace pdmesh;
using namespace pdmesh_test;
namespace fs = std::filesystem;

namespace {

const fs::path kAnisoLinear = fs::path(PDMESH_SOURCE_DIR) / "cases" / "aniso" / "linear" / "case.toml";
const fs::path kNacaLayers = fs::path(PDMESH_SOURCE_DIR) / "examples" / "naca0012_layers" / "case.toml";

CaseConfig parsed(const std::string& text, const std::vector<CaseOverride>& overrides = {}) {
  return parse_case_text(text, kCase, overrides);
}

}  // namespace

TEST_CASE("best's drift tolerance, steering, population stop and structured step per kind of run",
          "[app][case][convergence]") {
  for (const Preset p : {Preset::Best, Preset::Fast}) {
    CHECK(preset_stop_aspect(p, false) == 1.5e-3);
    CHECK(preset_stop_aspect(p, true) == 7e-4);
    CHECK(preset_momentum_mix(p, false) == 0.2);
    CHECK(preset_momentum_mix(p, true) == 0.0);
    CHECK(preset_population_stop(p, false) == 0.15);
    CHECK(preset_population_stop(p, true) == 0.15);
    CHECK(preset_dt_structured(p, false) == 0.016);
    CHECK_FALSE(preset_dt_structured(p, true).has_value());
  }
  const CaseConfig initializers;
  for (const Preset p : {Preset::Thesis, Preset::Long})
    for (const bool metric : {false, true}) {
      CHECK(preset_stop_aspect(p, metric) == initializers.simulation.stop_aspect);
      CHECK(preset_momentum_mix(p, metric) == initializers.simulation.momentum_mix);
      CHECK(preset_population_stop(p, metric) == initializers.population.stop);
      CHECK_FALSE(preset_dt_structured(p, metric).has_value());
    }

  // Parsed: the kind of run decides where the file leaves the keys out.
  for (const std::string& text : {kGeometry, "preset = \"fast\"\n" + kGeometry}) {
    const CaseConfig c = parsed(text);
    CHECK(c.simulation.stop_aspect == 1.5e-3);
    CHECK(c.simulation.momentum_mix == 0.2);
    CHECK(c.population.stop == 0.15);
    CHECK(c.simulation.dt_structured == 0.016);
    CHECK_FALSE(c.simulation.dt_random.has_value());  // a random start keeps the automatic rule
  }
  for (const std::string& text : {kGeometry + kMetric, kGeometry + kHessian}) {
    const CaseConfig c = parsed(text);
    CHECK(c.simulation.stop_aspect == 7e-4);
    CHECK(c.simulation.momentum_mix == 0.0);
    CHECK(c.population.stop == 0.15);
    CHECK_FALSE(c.simulation.dt_structured.has_value());
    // A step for the random start alone leaves the structured start's to the kind of run.
    const CaseConfig random_only = parsed(text + "[simulation]\ndt_initial = { random = 0.025 }\n");
    CHECK_FALSE(random_only.simulation.dt_structured.has_value());
    CHECK(random_only.simulation.dt_random == 0.025);
  }
  const CaseConfig linear = load_case_file(kAnisoLinear);
  CHECK(linear.simulation.stop_aspect == 7e-4);
  CHECK(linear.simulation.momentum_mix == 0.0);
  CHECK(linear.population.stop == 0.15);
  CHECK_FALSE(linear.simulation.dt_structured.has_value());
  // A run made metric by --set takes the metric values too.
  const CaseConfig made_metric =
      parsed(kGeometry, {parse_set_option("spacing.field=metric"), parse_set_option("spacing.h1=\"0.1\""),
                         parse_set_option("spacing.h2=\"0.01\"")});
  CHECK(made_metric.simulation.stop_aspect == 7e-4);
  CHECK(made_metric.simulation.momentum_mix == 0.0);
  CHECK(made_metric.population.stop == 0.15);
  CHECK_FALSE(made_metric.simulation.dt_structured.has_value());
  // The thesis preset keeps its own in either kind of run.
  const CaseConfig thesis = parsed("preset = \"thesis\"\n" + kGeometry + kMetric);
  CHECK(thesis.simulation.stop_aspect == initializers.simulation.stop_aspect);
  CHECK(thesis.simulation.momentum_mix == 0.0);
  CHECK(thesis.population.stop == initializers.population.stop);
  CHECK_FALSE(thesis.simulation.dt_structured.has_value());

  // The run gets them.
  const SimOptions iso = simulation_options(parsed(kGeometry));
  CHECK(iso.convergence.aspect_tolerance == 1.5e-3);
  CHECK(iso.momentum_mix == 0.2);
  CHECK(iso.dt_initial == 0.016);
  CHECK(iso.population.stop == 0.15);
  const SimOptions metric = simulation_options(linear);
  CHECK(metric.convergence.aspect_tolerance == 7e-4);
  CHECK(metric.momentum_mix == 0.0);
  CHECK_FALSE(metric.dt_initial.has_value());
  CHECK(metric.population.stop == 0.15);

  // apply_preset on a CaseConfig built in code looks at its field as it is then, and long leaves nothing.
  CaseConfig by_hand;
  by_hand.spacing.field = SpacingKind::Metric;
  apply_preset(by_hand, Preset::Best);
  CHECK(by_hand.simulation.stop_aspect == 7e-4);
  CHECK(by_hand.simulation.momentum_mix == 0.0);
  CHECK_FALSE(by_hand.simulation.dt_structured.has_value());
  by_hand.spacing.field = SpacingKind::Boundary;
  apply_preset(by_hand, Preset::Best);
  CHECK(by_hand.simulation.stop_aspect == 1.5e-3);
  CHECK(by_hand.simulation.momentum_mix == 0.2);
  CHECK(by_hand.population.stop == 0.15);
  CHECK(by_hand.simulation.dt_structured == 0.016);
  apply_preset(by_hand, Preset::Long);
  CHECK(by_hand.simulation.stop_aspect == initializers.simulation.stop_aspect);
  CHECK(by_hand.simulation.momentum_mix == initializers.simulation.momentum_mix);
  CHECK(by_hand.population.stop == initializers.population.stop);
  CHECK_FALSE(by_hand.simulation.dt_structured.has_value());
}

TEST_CASE("best's drift tolerance, population stop and step: a value the case sets wins in both kinds of run",
          "[app][case][convergence]") {
  const std::string keys =
      "[simulation]\nstop_aspect = 2e-3\ndt_initial = { structured = 0.05 }\n[population]\nstop = 0.5\n";
  for (const std::string& text : {kGeometry + keys, kGeometry + kMetric + keys}) {
    INFO(text);
    const CaseConfig c = parsed(text);
    CHECK(c.simulation.stop_aspect == 2e-3);
    CHECK(c.population.stop == 0.5);
    CHECK(c.simulation.dt_structured == 0.05);
  }
  const std::vector<CaseOverride> set = {parse_set_option("simulation.stop_aspect=2e-3"),
                                         parse_set_option("population.stop=0.5"),
                                         parse_set_option("simulation.dt_initial=0.05")};
  for (const std::string& text : {kGeometry, kGeometry + kMetric}) {
    INFO(text);
    const CaseConfig c = parsed(text, set);
    CHECK(c.simulation.stop_aspect == 2e-3);
    CHECK(c.population.stop == 0.5);
    CHECK(c.simulation.dt_structured == 0.05);
    CHECK(c.simulation.dt_random == 0.05);
  }
}

TEST_CASE(
    "pdmesh smooth keeps population control to 0.2, the drift tolerance 7e-4 and no steering, before the "
    "user's --set",
    "[smooth][case]") {
  for (const SmoothField field : {SmoothField::Mesh, SmoothField::Case}) {
    const std::vector<CaseOverride> defaults = smooth_overrides(field);
    const CaseConfig c = parsed(kGeometry, defaults);
    CHECK(c.population.stop == kSmoothPopulationStop);
    CHECK(c.simulation.stop_aspect == kSmoothStopAspect);
    CHECK(c.simulation.momentum_mix == 0.0);
    CHECK_FALSE(c.simulation.dt_structured.has_value());
    std::vector<CaseOverride> with_user = defaults;
    with_user.push_back(parse_set_option("population.stop=0.5"));
    with_user.push_back(parse_set_option("simulation.stop_aspect=2e-3"));
    with_user.push_back(parse_set_option("simulation.momentum_mix=0.3"));
    const CaseConfig u = parsed(kGeometry, with_user);
    CHECK(u.simulation.momentum_mix == 0.3);
    CHECK(u.population.stop == 0.5);
    CHECK(u.simulation.stop_aspect == 2e-3);
  }
  // They yield to the case file's own values, a step set as one number or per start included.
  for (const char* dt : {"dt_initial = 0.01\n", "dt_initial = { structured = 0.01 }\n"}) {
    INFO(dt);
    const CaseConfig own = parsed(kGeometry + "[simulation]\nstop_aspect = 2e-3\n" + dt + "[population]\nstop = 0.5\n",
                                  smooth_overrides(SmoothField::Case));
    CHECK(own.population.stop == 0.5);
    CHECK(own.simulation.stop_aspect == 2e-3);
    CHECK(own.simulation.dt_structured == 0.01);
  }
  const CaseConfig random_only =
      parsed(kGeometry + "[simulation]\ndt_initial = { random = 0.025 }\n", smooth_overrides(SmoothField::Case));
  CHECK_FALSE(random_only.simulation.dt_structured.has_value());
  CHECK(random_only.simulation.dt_random == 0.025);
  // The user's --set comes after them, for the whole step or one start's.
  for (const char* set : {"simulation.dt_initial=0.05", "simulation.dt_initial.structured=0.05"}) {
    std::vector<CaseOverride> with_user = smooth_overrides(SmoothField::Mesh);
    with_user.push_back(parse_set_option(set));
    CHECK(parsed(kGeometry, with_user).simulation.dt_structured == 0.05);
  }
  // Not the best preset's own for a mesh run.
  CHECK(parsed(kGeometry).population.stop != kSmoothPopulationStop);
  CHECK(parsed(kGeometry).simulation.stop_aspect != kSmoothStopAspect);
}

TEST_CASE("simulation.momentum_mix: 0.2 in best's isotropic runs, 0 elsewhere, and the run takes a value the case sets",
          "[app][case]") {
  for (const std::string& text : {kGeometry, "preset = \"fast\"\n" + kGeometry}) {
    INFO(text);
    CHECK(parsed(text).simulation.momentum_mix == 0.2);
    CHECK(simulation_options(parsed(text)).momentum_mix == 0.2);
  }
  for (const std::string& text :
       {kGeometry + kMetric, "preset = \"thesis\"\n" + kGeometry, "preset = \"long\"\n" + kGeometry}) {
    INFO(text);
    CHECK(parsed(text).simulation.momentum_mix == 0.0);
    CHECK(simulation_options(parsed(text)).momentum_mix == 0.0);
  }
  CHECK(load_case_file(kAnisoLinear).simulation.momentum_mix == 0.0);
  // A layered run's core is isotropic: it steers too.
  const CaseConfig layers = load_case_file(kNacaLayers);
  REQUIRE_FALSE(layers.boundary_layers.empty());
  CHECK(layers.simulation.momentum_mix == 0.2);
  CHECK(parsed(kGeometry, smooth_overrides(SmoothField::Case)).simulation.momentum_mix == 0.0);
  // A value the case or --set gives is the run's, in every kind of run.
  for (const std::string& text : {kGeometry, kGeometry + kMetric}) {
    INFO(text);
    const CaseConfig own = parsed(text + "[simulation]\nmomentum_mix = 0.2\n");
    CHECK(own.simulation.momentum_mix == 0.2);
    CHECK(simulation_options(own).momentum_mix == 0.2);
    CHECK(parsed(text, {parse_set_option("simulation.momentum_mix=0.5")}).simulation.momentum_mix == 0.5);
  }
  // The case reader's range.
  for (const char* bad : {"-0.1", "1", "1.5"}) {
    INFO(bad);
    CHECK_THROWS_WITH(parsed(kGeometry + "[simulation]\nmomentum_mix = " + bad + "\n"),
                      Catch::Contains("simulation.momentum_mix must be in [0, 1)"));
  }
}

TEST_CASE("simulation.dt_initial \"auto\" is the automatic rule, also under a preset that sets a step", "[app][case]") {
  CHECK_FALSE(parsed(kGeometry + "[simulation]\ndt_initial = \"auto\"\n").simulation.dt_structured.has_value());
  const CaseConfig per = parsed(kGeometry + "[simulation]\ndt_initial = { structured = \"auto\", random = 0.02 }\n");
  CHECK_FALSE(per.simulation.dt_structured.has_value());
  CHECK(per.simulation.dt_random == 0.02);
  const CaseConfig set = parsed(kGeometry, {parse_set_option("simulation.dt_initial.structured=auto")});
  CHECK_FALSE(set.simulation.dt_structured.has_value());
  CHECK_FALSE(simulation_options(set).dt_initial.has_value());
  CHECK_THROWS_WITH(parsed(kGeometry + "[simulation]\ndt_initial = \"fast\"\n"),
                    Catch::Contains("simulation.dt_initial must be a number > 0 or \"auto\", got 'fast'"));
  CHECK_THROWS_WITH(parsed(kGeometry + "[simulation]\ndt_initial = { structured = -1 }\n"),
                    Catch::Contains("simulation.dt_initial.structured must be > 0, got -1"));
}
