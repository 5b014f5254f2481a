// Heavy-ball momentum (SimOptions::momentum, docs/simulation.md "Momentum") over whole runs: the
// device-resident run repeats the host reference bit for bit in double with beta = 0.9 (both force
// loops; population events that renumber the nodes; snaps that turn interior nodes into boundary
// nodes), and a run stopped and resumed from its checkpoint is the uninterrupted run, bit for bit,
// on the host and on the device.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstdlib>

#include "sim/checkpoint.hpp"
#include "device_run_fixtures.hpp"

using namespace pdmesh;
using pdmesh::test::Case;
using pdmesh::test::Outcome;
using pdmesh::test::require_identical_nodes;

namespace {

void require_same_momentum(const SimState& a, const SimState& b) {
  REQUIRE(a.momentum.size() == b.momentum.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.momentum.size(); ++i)
    if (a.momentum[i].x != b.momentum[i].x || a.momentum[i].y != b.momentum[i].y) ++differ;
  CHECK(differ == 0);
}

// circle_circle from a random start with population control (events every 10 iterations from 20).
Case population_case() {
  return test::load_case("circle_circle", {{"init.method", "random", "test"},
                                           {"population.enabled", "true", "test"},
                                           {"population.start", "20", "test"},
                                           {"population.every", "10", "test"}});
}

SimOptions momentum_options(const Case& c, int iterations, double beta) {
  SimOptions o = test::options_for(c, iterations);
  o.population = c.config.population;
  o.momentum = beta;
  return o;
}

// Each force loop's device run of `o` repeats the host's run `host`: the history, the nodes and the
// carried moves.
void require_device_repeats_host(const Case& c, const SimOptions& o, const Outcome& host) {
  for (const ocl::ForceLoop loop : test::kForceLoops) {
    INFO(ocl::force_loop_name(loop) << " force loop");
    const Outcome dev = test::run_from(c, c.initial, o, true, false, loop);
    REQUIRE(dev.result.history.size() == host.result.history.size());
    for (std::size_t k = 0; k < host.result.history.size(); ++k) {
      INFO("iteration " << host.result.history[k].iteration);
      CHECK(dev.result.history[k].max_force == host.result.history[k].max_force);
      CHECK(dev.result.history[k].dt_gm == host.result.history[k].dt_gm);
      CHECK(dev.result.history[k].inserted == host.result.history[k].inserted);
      CHECK(dev.result.history[k].removed == host.result.history[k].removed);
    }
    require_identical_nodes(host.nodes, dev.nodes);
    require_same_momentum(host.result.state, dev.result.state);
  }
}

}  // namespace

TEST_CASE("momentum 0.9: the device run repeats the host over 300 iterations with population events",
          "[opencl][device_sim][momentum]") {
  const Case c = population_case();
  const SimOptions o = momentum_options(c, 300, 0.9);
  const Outcome host = test::run_from(c, c.initial, o, false);
  REQUIRE(host.result.stats.inserted + host.result.stats.removed > 0);
  REQUIRE(host.result.state.momentum.size() == host.nodes.size());
  // Momentum changed the run (else this test could not fail on a device that ignores it).
  const Outcome plain = test::run_from(c, c.initial, momentum_options(c, 300, 0.0), false);
  CHECK(plain.result.history.back().max_force != host.result.history.back().max_force);
  CHECK(plain.result.state.momentum.empty());
  require_device_repeats_host(c, o, host);
}

// The carried moves steered towards the force (SimOptions::momentum_mix, 0.2 in the best preset's
// isotropic runs): the device's step repeats the host's steering operation for operation.
TEST_CASE("momentum 0.9 with mix 0.2: the device run repeats the host over 300 iterations with population events",
          "[opencl][device_sim][momentum]") {
  const Case c = population_case();
  SimOptions o = momentum_options(c, 300, 0.9);
  o.momentum_mix = 0.2;
  const Outcome host = test::run_from(c, c.initial, o, false);
  REQUIRE(host.result.stats.inserted + host.result.stats.removed > 0);
  // The mix changed the run (else this test could not fail on a device that ignores it).
  const Outcome unmixed = test::run_from(c, c.initial, momentum_options(c, 300, 0.9), false);
  CHECK(unmixed.result.history.back().max_force != host.result.history.back().max_force);
  require_device_repeats_host(c, o, host);
}

TEST_CASE("momentum 0.9: snaps (interior nodes that become boundary nodes) on the device as on the host",
          "[opencl][device_sim][momentum]") {
  const Case c = test::load_case("shock", {parse_set_option("init.method=structured")});
  SimOptions o = test::options_for(c, 100);
  o.momentum = 0.9;
  const Outcome host = test::run_from(c, c.initial, o, false);
  REQUIRE(host.result.stats.snapped > 0);
  for (const ocl::ForceLoop loop : test::kForceLoops) {
    INFO(ocl::force_loop_name(loop) << " force loop");
    const Outcome dev = test::run_from(c, c.initial, o, true, false, loop);
    CHECK(dev.result.stats.snapped == host.result.stats.snapped);
    require_identical_nodes(host.nodes, dev.nodes);
    require_same_momentum(host.result.state, dev.result.state);
  }
}

TEST_CASE("momentum 0.9: a run stopped, saved and resumed is the uninterrupted run, bit for bit",
          "[momentum][resume]") {
  const Case c = population_case();
  const SimOptions whole = momentum_options(c, 120, 0.9);
  const Outcome uninterrupted = test::run_from(c, c.initial, whole, false);
  // Stopped after 55 iterations of the same 120 (between population events; a shorter run would ramp
  // population control's thresholds to its own end), through the checkpoint's text.
  std::atomic<bool> stop{false};
  SimOptions stopped = whole;
  stopped.stop = &stop;
  SimCallbacks callbacks;
  callbacks.on_iteration = [&stop](const HistoryRow& row) {
    if (row.iteration == 55) stop = true;
  };
  Outcome first{c.initial, {}, {}};
  first.result = run_simulation(first.nodes, c.inputs->node_tree(), *c.inputs->spacing, stopped, callbacks);
  REQUIRE(first.result.stopped);
  REQUIRE(first.result.state.iterations_done == 55);
  REQUIRE(first.result.state.momentum.size() == first.nodes.size());
  Checkpoint saved{{{"simulation.momentum", "0.9"}}, first.nodes, first.result.state};
  const Checkpoint read = parse_checkpoint(format_checkpoint(saved), "test checkpoint");
  require_same_momentum(first.result.state, read.state);
  for (const bool device : {false, true}) {
    INFO((device ? "device" : "host") << " resume");
    SimOptions rest = whole;
    rest.resume = &read.state;
    const Outcome resumed = test::run_from(c, read.nodes, rest, device);
    REQUIRE(resumed.result.history.size() == uninterrupted.result.history.size());
    require_identical_nodes(uninterrupted.nodes, resumed.nodes);
    require_same_momentum(uninterrupted.result.state, resumed.result.state);
  }
}

namespace {

// The device begins the next window while the host measures a check's mesh (DeviceRun's run_ahead);
// at the check the run stops after, what it ran ahead is dropped and the state is the check's,
// its carried moves included. Against the same run without running ahead and the host's. skin < 0:
// the options' own Verlet skin.
void require_run_ahead_changes_nothing(double skin) {
  const Case c = population_case();
  SimOptions o = momentum_options(c, 600, 0.9);
  if (skin >= 0.0) o.verlet_skin = skin;
  o.convergence = simulation_options(c.config).convergence;
  o.convergence.enabled = true;
  o.convergence.check_every = 20;
  o.convergence.window = 60;
  o.convergence.min_iterations = 100;
  const Outcome host = test::run_from(c, c.initial, o, false);
  REQUIRE(host.result.converged);
  INFO("the host run converged after " << host.result.state.iterations_done);
  // While the device runs ahead the saved positions are freed and read back after the check: the
  // run throws if what comes back is not the saved state bit for bit.
  // One window ahead (the overlapped measurement, which also builds ahead, has its own test:
  // test_device_measure_overlap.cpp).
  ::setenv("PDMESH_TEST_CHECK_SAVED_RESTORE", "1", 1);
  ::setenv("PDMESH_MEASURE_OVERLAP", "0", 1);
  const Outcome ahead = test::run_from(c, c.initial, o, true);
  ::unsetenv("PDMESH_MEASURE_OVERLAP");
  ::unsetenv("PDMESH_TEST_CHECK_SAVED_RESTORE");
  ::setenv("PDMESH_TEST_NO_RUN_AHEAD", "1", 1);
  const Outcome in_step = test::run_from(c, c.initial, o, true);
  ::unsetenv("PDMESH_TEST_NO_RUN_AHEAD");
  CHECK(ahead.stats.ahead_windows > 0);
  CHECK(in_step.stats.ahead_windows == 0);
  // The checks the device ran ahead of read the saved state back (in float not before the second build).
  CHECK(ahead.stats.saved_restores > 0);
  CHECK(ahead.stats.saved_restores <= ahead.stats.ahead_windows);
  CHECK(in_step.stats.saved_restores == 0);
  CHECK(ahead.stats.iterations == in_step.stats.iterations);
  // skin >= 0 builds before the converged check too: ahead of an iteration the stop then drops.
  CHECK(ahead.stats.rebuilds == in_step.stats.rebuilds + (skin >= 0.0 ? 1 : 0));
  for (const Outcome* dev : {&ahead, &in_step}) {
    CHECK(dev->result.converged);
    CHECK(dev->result.state.iterations_done == host.result.state.iterations_done);
    REQUIRE(dev->result.history.size() == host.result.history.size());
    CHECK(dev->result.history.back().max_force == host.result.history.back().max_force);
    require_identical_nodes(host.nodes, dev->nodes);
    require_same_momentum(host.result.state, dev->result.state);
    REQUIRE(dev->result.state.convergence.size() == host.result.state.convergence.size());
    CHECK(dev->result.state.convergence.back().aspect_ratio == host.result.state.convergence.back().aspect_ratio);
  }
  if (skin >= 0.0) {
    INFO(ahead.stats.rebuilds << " builds in " << ahead.stats.iterations << " iterations");
    CHECK(2 * ahead.stats.rebuilds > ahead.stats.iterations);
  }
}

}  // namespace

TEST_CASE("momentum 0.9 with the convergence rule: running ahead of the checks changes nothing, the stop included",
          "[opencl][device_sim][momentum][convergence]") {
  require_run_ahead_changes_nothing(-1.0);
}

TEST_CASE("momentum 0.9 with the convergence rule and a build before every check: the stop's carried moves",
          "[opencl][device_sim][momentum][convergence]") {
  // With a skin of 1e-6 the lists are built before nearly every iteration (one iteration uses the
  // skin up), so the build before the converged check read the carried moves the run stops with
  // (DeviceRun::check_momentum_saved_): what the device ran ahead must not be taken for them.
  require_run_ahead_changes_nothing(1e-6);
}

TEST_CASE("momentum 0.9 with the convergence rule and a zero skin: a build every iteration, ahead of the checks too",
          "[opencl][device_sim][momentum][convergence]") {
  // A zero skin builds before every iteration; the window run ahead of a check starts with its own
  // build, and the iteration it begins must not build again.
  require_run_ahead_changes_nothing(0.0);
}
