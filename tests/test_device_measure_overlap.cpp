// The overlapped measurement (DeviceRun::run_ahead, PDMESH_MEASURE_OVERLAP): while the host measures
// a convergence check's mesh, the device runs on through windows and neighbour-list builds; their rows
// are held back and taken by the loop once the rule has gone on, or dropped when it stops the run
// there. The run must be the run without it, bit for bit: every history row once, in order, the
// converged check's state (nodes, carried moves, measurements) and nothing of what ran past it.
// On PoCL with PDMESH_MEASURE_OVERLAP=full: the device runs ahead to where the host must act however
// soon the measurement ends, so the same iterations are run ahead on every machine.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "io/text_file.hpp"
#include "device_run_fixtures.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using pdmesh::test::Case;
using pdmesh::test::Outcome;
using pdmesh::test::require_identical_nodes;
using pdmesh_test::fresh_path;
using pdmesh_test::run_pdmesh;
namespace fs = std::filesystem;

namespace {

// circle_circle from a random start, population events every 10 iterations from 20 to 120, the rule
// measured every 25 iterations.
Case overlap_case() {
  return test::load_case("circle_circle", {{"init.method", "random", "test"},
                                           {"population.enabled", "true", "test"},
                                           {"population.start", "20", "test"},
                                           {"population.every", "10", "test"},
                                           {"population.stop", "0.2", "test"}});
}

SimOptions overlap_options(const Case& c, double momentum, double skin) {
  SimOptions o = test::options_for(c, momentum > 0.0 ? 600 : 2000);
  o.population = c.config.population;
  o.momentum = momentum;
  o.verlet_skin = skin;
  o.convergence = simulation_options(c.config).convergence;
  o.convergence.enabled = true;
  o.convergence.check_every = 25;
  o.convergence.window = 75;
  o.convergence.min_iterations = 150;
  return o;
}

Outcome device_run(const Case& c, const SimOptions& o, const char* overlap) {
  if (overlap)
    ::setenv("PDMESH_MEASURE_OVERLAP", overlap, 1);
  else
    ::unsetenv("PDMESH_MEASURE_OVERLAP");
  // The saved positions freed during a check and read back after it must be the saved ones, bit for bit.
  ::setenv("PDMESH_TEST_CHECK_SAVED_RESTORE", "1", 1);
  Outcome out = test::run_from(c, c.initial, o, true);
  ::unsetenv("PDMESH_TEST_CHECK_SAVED_RESTORE");
  ::unsetenv("PDMESH_MEASURE_OVERLAP");
  return out;
}

// Every row once, in order, the same. The sums (averages) of two device runs are the same bit for bit;
// the host's are summed in another order.
void require_same_rows(const std::vector<HistoryRow>& a, const std::vector<HistoryRow>& b, bool sums) {
  REQUIRE(a.size() == b.size());
  std::size_t differ = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].iteration != static_cast<int>(k) + 1 || b[k].iteration != a[k].iteration ||
        a[k].max_force != b[k].max_force || a[k].dt_gm != b[k].dt_gm || a[k].snapped != b[k].snapped ||
        a[k].inserted != b[k].inserted || a[k].removed != b[k].removed || a[k].interior != b[k].interior ||
        a[k].boundary != b[k].boundary ||
        (sums && (a[k].average_force != b[k].average_force || a[k].average_kinetic != b[k].average_kinetic ||
                  a[k].clamped != b[k].clamped)))
      ++differ;
  CHECK(differ == 0);
}

void require_same_state(const Outcome& a, const Outcome& b, bool sums) {
  CHECK(a.result.converged == b.result.converged);
  CHECK(a.result.state.iterations_done == b.result.state.iterations_done);
  require_same_rows(a.result.history, b.result.history, sums);
  require_same_rows(a.result.state.history, b.result.state.history, sums);
  require_identical_nodes(a.nodes, b.nodes);
  REQUIRE(a.result.state.momentum.size() == b.result.state.momentum.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.result.state.momentum.size(); ++i)
    if (a.result.state.momentum[i].x != b.result.state.momentum[i].x ||
        a.result.state.momentum[i].y != b.result.state.momentum[i].y)
      ++differ;
  CHECK(differ == 0);
  REQUIRE(a.result.state.convergence.size() == b.result.state.convergence.size());
  for (std::size_t k = 0; k < a.result.state.convergence.size(); ++k) {
    CHECK(a.result.state.convergence[k].iteration == b.result.state.convergence[k].iteration);
    CHECK(a.result.state.convergence[k].aspect_ratio == b.result.state.convergence[k].aspect_ratio);
  }
}

void require_overlap_changes_nothing(double momentum, double skin) {
  const Case c = overlap_case();
  const SimOptions o = overlap_options(c, momentum, skin);
  const Outcome host = test::run_from(c, c.initial, o, false);
  REQUIRE(host.result.converged);
  INFO("the host run converged after " << host.result.state.iterations_done);
  const Outcome one_window = device_run(c, o, "0");
  const Outcome overlapped = device_run(c, o, "full");
  INFO(overlapped.stats.ahead_rows << " rows and " << overlapped.stats.ahead_rebuilds << " builds run ahead, "
                                   << overlapped.stats.ahead_windows << " windows");
  CHECK(one_window.stats.ahead_rows == 0);
  // Windows and builds were run ahead of the checks, and the stop dropped what ran past the last one.
  CHECK(overlapped.stats.ahead_rows > 0);
  CHECK(overlapped.stats.ahead_rebuilds > 0);
  CHECK(overlapped.stats.iterations == one_window.stats.iterations);
  for (const Outcome* dev : {&one_window, &overlapped}) require_same_state(host, *dev, false);
  require_same_state(one_window, overlapped, true);
  // The list entries of the iterations taken, not of those dropped.
  CHECK(overlapped.result.stats.pairs_examined == one_window.result.stats.pairs_examined);
}

}  // namespace

TEST_CASE("overlapped measurement, momentum 0.9: held rows taken once, in order, the converged check's state",
          "[opencl][device_sim][momentum][convergence]") {
  // The best preset's momentum; a skin small enough that builds come between the checks.
  require_overlap_changes_nothing(0.9, 0.05);
}

TEST_CASE("overlapped measurement without momentum: the same run bit for bit", "[opencl][device_sim][convergence]") {
  require_overlap_changes_nothing(0.0, 0.05);
}

TEST_CASE("overlapped measurement with the options' own skin: the same run bit for bit",
          "[opencl][device_sim][momentum][convergence]") {
  require_overlap_changes_nothing(0.9, auto_verlet_skin(0.9, 0));
}

TEST_CASE("overlapped measurement with a zero skin: a build before every iteration run ahead",
          "[opencl][device_sim][momentum][convergence]") {
  require_overlap_changes_nothing(0.9, 0.0);
}

TEST_CASE("a device lost while it runs ahead of the checks: the last good state resumes to the uninterrupted run",
          "[failures][opencl][cli][convergence]") {
  // The 30P30N curves (best preset: checks every 50 iterations from 150), the device running ahead of
  // every check. The faults land at OpenCL calls spread over the run (ahead of a check, while the
  // held rows are taken, in ordinary windows): each run that fails hands over a good state, and the
  // run resumed from its checkpoint ends with the uninterrupted run's nodes and history, bit for bit.
  const std::string curves =
      "'" PDMESH_SOURCE_DIR "/cases/30p30n/airfoil.crv' '" PDMESH_SOURCE_DIR "/cases/30p30n/farfield.crv'";
  const std::string env = "PDMESH_MEASURE_OVERLAP=full";
  const fs::path whole = fresh_path("overlap_whole");
  const auto uninterrupted = run_pdmesh("mesh " + curves + " --out '" + whole.string() + "' --formats msh -q", env);
  INFO(uninterrupted.output);
  REQUIRE(uninterrupted.status == 0);
  int failed = 0;
  for (const int fault : {1200, 2200, 3300}) {
    INFO("PDMESH_TEST_FAIL_CL_AT=" << fault);
    const fs::path dir = fresh_path("overlap_lost");
    const std::string args = "mesh " + curves + " --out '" + dir.string() + "' --formats msh -q";
    const auto r = run_pdmesh(args, env + " PDMESH_TEST_FAIL_CL_AT=" + std::to_string(fault));
    INFO(r.output);
    if (r.status == 0) {  // the run made fewer calls
      fs::remove_all(dir);
      continue;
    }
    ++failed;
    CHECK(r.status == 1);
    REQUIRE(fs::exists(dir / "checkpoint.pdmesh"));
    const auto resumed = run_pdmesh(args + " --resume '" + dir.string() + "'", env);
    INFO(resumed.output);
    REQUIRE(resumed.status == 0);
    for (const char* file : {"final.nodes", "history.csv", "mesh.msh"}) {
      INFO(file);
      CHECK(read_text_file(dir / file) == read_text_file(whole / file));
    }
    fs::remove_all(dir);
  }
  CHECK(failed > 0);
  fs::remove_all(whole);
}

TEST_CASE("PDMESH_MEASURE_OVERLAP other than 0, 1 or full is an input error naming it", "[opencl][cli]") {
  const fs::path dir = fresh_path("overlap_bad_value");
  const auto r = run_pdmesh(
      "mesh '" PDMESH_SOURCE_DIR "/cases/circle_circle/case.toml' --out '" + dir.string() + "' --device opencl -q",
      "PDMESH_MEASURE_OVERLAP=off");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("PDMESH_MEASURE_OVERLAP must be 0, 1 or full, got 'off'") != std::string::npos);
  fs::remove_all(dir);
}
