// The stopping rule judged from population control's last change on too (ConvergenceOptions::
// from_last_event, simulation.stop_from_event): when an event that changed the node set ran inside the
// window, the window from the first measurement after it converges as well; the
// key per preset and kind of run (best: on for an isotropic run without boundary layers, off in a metric
// or with layers; thesis and long: off),
// a case's value wins, and pdmesh smooth keeps the whole window.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/smooth_pipeline.hpp"
#include "core/errors.hpp"
#include "sim/convergence.hpp"
#include "case_texts.hpp"
#include "convergence_fixtures.hpp"

using namespace pdmesh;
using namespace pdmesh_test;

namespace {

ConvergenceOptions options(bool from_last_event) {
  ConvergenceOptions o = small_convergence_options();
  o.from_last_event = from_last_event;
  return o;
}

// A settled mesh whose mean aspect ratio an event after iteration 50 lowers in one step of 0.01 (the
// measurement after iteration 50 is taken after the event); it wobbles within the tolerance otherwise.
MeshSample stepped(int iteration) {
  const double wobble = (iteration / 10) % 2 == 0 ? 1e-4 : -1e-4;
  return {iteration, 30.0, (iteration < 50 ? 1.05 : 1.04) + wobble};
}

// Feeds iterations 1 .. last with the (not quiet) event after `event`, and returns the first converged
// one, or 0.
int first_converged(ConvergenceMonitor& monitor, int last, int event) {
  for (int it = 1; it <= last; ++it) {
    HistoryRow row;
    row.iteration = it;
    std::optional<MeshSample> s;
    if (monitor.due(it)) s = stepped(it);
    if (monitor.observe(row, s ? &*s : nullptr, true, it >= event ? event : 0)) return it;
  }
  return 0;
}

const std::string kLayers =
    "[[boundary_layer]]\ncurves = [\"c0\"]\nfirst_height = 1e-3\ngrowth = 1.2\nthickness = 0.01\n";

CaseConfig parsed(const std::string& text, const std::vector<CaseOverride>& overrides = {}) {
  return parse_case_text(text, kCase, overrides);
}

}  // namespace

TEST_CASE("stop from the last event: the event's step no longer holds the rule for a whole window", "[convergence]") {
  // The whole window holds the step until it has passed: 50-90.
  ConvergenceMonitor whole(options(false));
  CHECK(first_converged(whole, 300, 50) == 90);
  // From the event on: one measurement interval after it, at 60.
  ConvergenceMonitor from_event(options(true));
  CHECK(first_converged(from_event, 300, 50) == 60);
  // An event before the window changes nothing: the step at 50 is inside 20-60, an event after 10 is not.
  std::vector<MeshSample> samples;
  for (int it = 10; it <= 60; it += 10) samples.push_back(stepped(it));
  const ConvergenceMonitor m(options(true), samples);
  CHECK_FALSE(m.converged_after(60, true, 10));
  CHECK(m.converged_after(60, true, 50));
}

TEST_CASE("stop from the last event: the whole window decides while no interval follows the event", "[convergence]") {
  std::vector<MeshSample> samples;
  for (int it = 10; it <= 50; it += 10) samples.push_back(stepped(it));
  // The event after the newest measurement leaves no interval after it: the whole window's verdict.
  const ConvergenceMonitor m(options(true), samples);
  CHECK_FALSE(m.converged_after(50, true, 50));
  CHECK(m.not_converged_reason(50, true, 50) ==
        "the mean aspect ratio of the triangulated nodes changed by 0.01 over iterations 10-50 (tolerance 0.0005)");
  // A whole window that converges does so even with an event right before its newest measurement.
  std::vector<MeshSample> flat;
  for (int it = 10; it <= 50; it += 10) flat.push_back({it, 30.0, 1.04});
  CHECK(ConvergenceMonitor(options(true), flat).converged_after(50, true, 50));
  // An event between measurements: the window from the first one after it.
  samples.push_back(stepped(60));
  CHECK(ConvergenceMonitor(options(true), samples).converged_after(60, true, 45));
  CHECK_FALSE(ConvergenceMonitor(options(true), samples).converged_after(60, true, 55));
}

TEST_CASE("simulation.stop_from_event: best isotropic on, metric and the other presets off, a case's value wins",
          "[case][convergence]") {
  CHECK(preset_stop_from_event(Preset::Best, false, false));
  CHECK(preset_stop_from_event(Preset::Fast, false, false));
  CHECK_FALSE(preset_stop_from_event(Preset::Best, true, false));
  CHECK_FALSE(preset_stop_from_event(Preset::Best, false, true));
  CHECK_FALSE(preset_stop_from_event(Preset::Thesis, false, false));
  CHECK_FALSE(preset_stop_from_event(Preset::Long, false, false));
  CHECK(parsed(kGeometry).simulation.stop_from_event);
  CHECK_FALSE(parsed(kGeometry + kMetric).simulation.stop_from_event);
  CHECK_FALSE(parsed(kGeometry + kLayers).simulation.stop_from_event);
  CHECK(parsed(kGeometry + kLayers + "[simulation]\nstop_from_event = true\n").simulation.stop_from_event);
  CHECK_FALSE(parsed("preset = \"thesis\"\n" + kGeometry).simulation.stop_from_event);
  CHECK_FALSE(parsed("preset = \"long\"\n" + kGeometry).simulation.stop_from_event);
  CHECK_FALSE(parsed(kGeometry + "[simulation]\nstop_from_event = false\n").simulation.stop_from_event);
  CHECK(parsed(kGeometry + kMetric + "[simulation]\nstop_from_event = true\n").simulation.stop_from_event);
  CHECK(simulation_options(parsed(kGeometry)).convergence.from_last_event);
  CHECK_FALSE(simulation_options(parsed(kGeometry + kMetric)).convergence.from_last_event);
  CHECK_THROWS_AS(parsed(kGeometry + "[simulation]\nstop_from_event = 1\n"), InputError);
  // pdmesh smooth keeps the whole window unless the case or the user says otherwise.
  CHECK_FALSE(parsed(kGeometry, smooth_overrides(SmoothField::Case)).simulation.stop_from_event);
  CHECK(parsed(kGeometry + "[simulation]\nstop_from_event = true\n", smooth_overrides(SmoothField::Case))
            .simulation.stop_from_event);
  std::vector<CaseOverride> with_user = smooth_overrides(SmoothField::Mesh);
  with_user.push_back(parse_set_option("simulation.stop_from_event=true"));
  CHECK(parsed(kGeometry, with_user).simulation.stop_from_event);
}
