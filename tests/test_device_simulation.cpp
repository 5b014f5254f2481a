// The device-resident simulation (host/opencl/device_simulation.cpp) against the host reference on
// the cases in cases/: 10 iterations node by node, and a whole run compared by mesh quality. The
// node-by-node tests run with both force loops (kernels/forces.cl: vector, scalar), whatever the device
// would choose, so the GPU-shaped loop is checked bit for bit on PoCL too.
// Tolerances: double, 10 iterations: |x_device - x_host| <= 1e-9 q per node (the kernels repeat the
// reference's arithmetic, so in practice the runs agree bit for bit); kinds and boundary order exact.
// Float, 10 iterations: 2e-2 q (measured 6.6e-3: the unsettled start amplifies rounding). Whole run: same triangle
// count, min angle within 0.5 degrees, average aspect ratio within 1%.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "device_run_fixtures.hpp"
#include "scoped_env.hpp"

using namespace pdmesh;
using pdmesh::test::Case;
using pdmesh::test::options_for;
using pdmesh::test::Outcome;
using pdmesh::test::require_identical_nodes;

namespace {

void require_same_nodes(const NodeSet& host, const NodeSet& dev, double tol_q) {
  REQUIRE(dev.size() == host.size());
  REQUIRE(dev.kind == host.kind);
  REQUIRE(dev.curve_nodes == host.curve_nodes);
  double worst = 0.0;
  std::size_t worst_node = 0;
  for (std::size_t i = 0; i < host.size(); ++i) {
    const double d = norm(dev.x[i] - host.x[i]) / host.q[i];
    if (d > worst) {
      worst = d;
      worst_node = i;
    }
  }
  INFO("worst node " << worst_node << ": " << worst << " q apart");
  CHECK(worst <= tol_q);
  for (std::size_t i = 0; i < host.size(); ++i)
    REQUIRE(std::fabs(dev.q[i] - host.q[i]) <= 1e-6 * host.q[i] + tol_q * host.q[i]);
}

}  // namespace

TEST_CASE("device run: 10 iterations agree with the host node by node (double)", "[opencl][device_sim]") {
  // The third: boundary nodes placed by the field on smooth curves, which both runs slide on.
  const std::vector<CaseOverride> smooth = {parse_set_option("geometry.curves=smooth"),
                                            parse_set_option("boundary.nodes=spacing")};
  for (const char* name : {"circle_circle", "naca0012", "circle_circle+smooth"}) {
    INFO(name);
    const bool is_smooth = std::string(name) == "circle_circle+smooth";
    const Case c =
        test::load_case(is_smooth ? "circle_circle" : name, is_smooth ? smooth : std::vector<CaseOverride>{});
    if (is_smooth) REQUIRE(c.inputs->dense);
    const Outcome host = test::run_case(c, 10, false);
    for (const auto& [skin, loop] : {std::pair{0.0, ocl::ForceLoop::Vector},
                                     {0.3, ocl::ForceLoop::Vector},
                                     {0.0, ocl::ForceLoop::Scalar},
                                     {0.3, ocl::ForceLoop::Scalar}}) {
      INFO("skin " << skin << ", " << ocl::force_loop_name(loop) << " force loop");
      const Outcome dev = test::run_case(c, 10, true, false, skin, loop);
      require_same_nodes(host.nodes, dev.nodes, 1e-9);
      REQUIRE(dev.result.history.size() == host.result.history.size());
      for (std::size_t k = 0; k < host.result.history.size(); ++k) {
        const HistoryRow &h = host.result.history[k], &d = dev.result.history[k];
        CHECK(d.max_force == Approx(h.max_force).epsilon(1e-12));
        CHECK(d.average_force == Approx(h.average_force).epsilon(1e-10));
        CHECK(d.average_kinetic == Approx(h.average_kinetic).epsilon(1e-10));
        CHECK(d.dt_gm == h.dt_gm);
        CHECK(d.snapped == h.snapped);
        CHECK(d.clamped == h.clamped);
        CHECK(d.interior == h.interior);
        CHECK(d.boundary == h.boundary);
      }
      CHECK(dev.result.stats.pairs_within == host.result.stats.pairs_within);
      // Traffic: per iteration less than one coordinate per node comes back (rebuilds excluded,
      // which download x, y, q once each), and few interior nodes need the host's exact test.
      const double n = static_cast<double>(c.initial.size());
      const double rebuild_bytes = 3.0 * n * sizeof(double) * (dev.stats.rebuilds - 1);
      CHECK((static_cast<double>(dev.stats.bytes_down) - rebuild_bytes) / 10.0 < 8.0 * n);
      CHECK(static_cast<double>(dev.stats.candidates) / 10.0 < 0.1 * n);
    }
  }
}

// The two ends of an iteration: the device's (iteration_rule, windows of iterations without a wait)
// and the host's (devices without cl_khr_fp64: the partials read every iteration), both the host
// reference's run bit for bit, history included; and a window does its iterations with one wait.
TEST_CASE("device run: windows with the device's time-step rule and the host's rule repeat the host",
          "[opencl][device_sim]") {
  const Case c = test::load_case("naca0012");
  const Outcome host = test::run_case(c, 60, false);
  std::vector<HistoryRow> device_rows;  // of the device's rule, to compare the host's rule with
  for (const bool host_rule : {false, true}) {
    INFO((host_rule ? "the host's rule" : "the device's rule"));
    if (host_rule) ::setenv("PDMESH_TEST_HOST_TIME_STEP_RULE", "1", 1);
    const Outcome dev = test::run_case(c, 60, true);
    ::unsetenv("PDMESH_TEST_HOST_TIME_STEP_RULE");
    require_identical_nodes(host.nodes, dev.nodes);
    REQUIRE(dev.result.history.size() == host.result.history.size());
    for (std::size_t k = 0; k < host.result.history.size(); ++k) {
      const HistoryRow &h = host.result.history[k], &d = dev.result.history[k];
      INFO("iteration " << h.iteration);
      CHECK(d.iteration == h.iteration);
      // The sums over work-groups are in another order than the reference's loop (docs/opencl.md), but
      // both rules sum the same partials in the same order: their rows are the same bit for bit.
      CHECK(d.average_force == Approx(h.average_force).epsilon(1e-10));
      CHECK(d.average_kinetic == Approx(h.average_kinetic).epsilon(1e-10));
      if (host_rule) {
        CHECK(d.average_force == device_rows[k].average_force);
        CHECK(d.average_kinetic == device_rows[k].average_kinetic);
      }
      CHECK(d.max_force == h.max_force);
      CHECK(d.dt_gm == h.dt_gm);
      CHECK(d.snapped == h.snapped);
      CHECK(d.clamped == h.clamped);
    }
    CHECK(dev.result.state.time_step.dt == host.result.state.time_step.dt);
    CHECK(dev.result.state.time_step.increases == host.result.state.time_step.increases);
    CHECK(dev.result.state.time_step.consecutive_decreases == host.result.state.time_step.consecutive_decreases);
    CHECK(dev.result.stats.pairs_within == host.result.stats.pairs_within);
    // The device's rule runs whole windows (fewer than one per iteration); the host's one per iteration.
    if (host_rule)
      CHECK(dev.stats.windows == 60);
    else
      CHECK(dev.stats.windows < 60);
    if (!host_rule) device_rows = dev.result.history;
  }
  // The rule changed dt in these iterations (else the comparison of dt would say little).
  CHECK(host.result.state.time_step.dt != c.config.simulation.dt_for(c.config.init.method));
}

// The GPU shape's rule (ForceLoop::Scalar, PDMESH_RULE_GROUP: the whole last group of boundary_snap_rule,
// or iteration_rule launched as one group) sums the same partials as the host's rule does (devices
// without cl_khr_fp64: DeviceWindow::complete, one after the other in group order), in double and float:
// the same history bit for bit. Chunks of 8 step groups (PDMESH_TEST_RULE_CHUNK) so that these small
// runs stage many chunks, the last one partial, as millions of nodes do with the default chunk.
TEST_CASE("device run: the rule by a whole work-group sums as the host's rule, bit for bit", "[opencl][device_sim]") {
  Case held = test::load_case("circle_circle");  // no boundary nodes: iteration_rule
  for (auto& k : held.initial.kind)
    if (k == NodeKind::Boundary) k = NodeKind::Fixed;
  const Case with_boundary = test::load_case("naca0012");  // boundary_snap_rule's last group
  const pdmesh_test::ScopedEnv chunk("PDMESH_TEST_RULE_CHUNK", "8");
  for (const Case* c : {&with_boundary, static_cast<const Case*>(&held)}) {
    INFO((c == &held ? "circle_circle without boundary nodes" : "naca0012"));
    REQUIRE(c->initial.size() > 3 * 8 * ocl::kStepWorkGroup);  // 3 chunks at least
    for (const bool use_float : {false, true}) {
      INFO((use_float ? "float" : "double"));
      SimOptions o = options_for(*c, 20);
      o.window_seconds = 0.0;  // windows as long as the ring, however slow the device (Oclgrind)
      const Outcome group = test::run_from(*c, c->initial, o, true, use_float, ocl::ForceLoop::Scalar);
      const Outcome host_rule = [&] {
        const pdmesh_test::ScopedEnv host("PDMESH_TEST_HOST_TIME_STEP_RULE", "1");
        return test::run_from(*c, c->initial, o, true, use_float, ocl::ForceLoop::Scalar);
      }();
      CHECK(group.stats.windows < 20);  // the device's rule ran
      CHECK(host_rule.stats.windows == 20);
      require_identical_nodes(host_rule.nodes, group.nodes);
      REQUIRE(group.result.history.size() == host_rule.result.history.size());
      for (std::size_t k = 0; k < group.result.history.size(); ++k) {
        const HistoryRow &h = host_rule.result.history[k], &d = group.result.history[k];
        INFO("iteration " << h.iteration);
        CHECK(d.average_force == h.average_force);
        CHECK(d.average_kinetic == h.average_kinetic);
        CHECK(d.max_force == h.max_force);
        CHECK(d.dt_gm == h.dt_gm);
        CHECK(d.snapped == h.snapped);
        CHECK(d.clamped == h.clamped);
        CHECK(d.interior == h.interior);
      }
      CHECK(group.result.stats.pairs_within == host_rule.result.stats.pairs_within);
      CHECK(group.result.state.time_step.dt == host_rule.result.state.time_step.dt);
    }
  }
}

// With boundary nodes the rule runs in boundary_snap_rule's last work-group; without any (here every
// boundary node of circle_circle held as a fixed node) no boundary_snap runs and the kernel
// iteration_rule runs the same rule (kernels/window.cl): both repeat the host bit for bit.
TEST_CASE("device run without boundary nodes: the rule's own kernel repeats the host", "[opencl][device_sim]") {
  Case c = test::load_case("circle_circle");
  int boundary = 0;
  for (auto& k : c.initial.kind)
    if (k == NodeKind::Boundary) {
      k = NodeKind::Fixed;
      ++boundary;
    }
  REQUIRE(boundary > 0);
  const Outcome host = test::run_case(c, 40, false);
  const Outcome dev = test::run_case(c, 40, true);
  require_identical_nodes(host.nodes, dev.nodes);
  REQUIRE(dev.result.history.size() == host.result.history.size());
  for (std::size_t k = 0; k < host.result.history.size(); ++k) {
    INFO("iteration " << host.result.history[k].iteration);
    CHECK(dev.result.history[k].max_force == host.result.history[k].max_force);
    CHECK(dev.result.history[k].dt_gm == host.result.history[k].dt_gm);
  }
  CHECK(dev.stats.windows < 40);  // the device's rule: windows of several iterations
  CHECK(dev.result.state.time_step.dt == host.result.state.time_step.dt);
}

// A snap the Verlet skin does not rebuild for left the snapped node its stale interior row (and its new
// curve neighbours their old rows): on shock from the structured start 4 nodes snap at iteration 11
// with skin use 0.24, and the device run left the host there (0.28 q apart after 100 iterations).
TEST_CASE(
    "device run: shock from the structured start is bit-identical to the host over 100 iterations "
    "(snaps the skin alone would not rebuild for)",
    "[opencl][device_sim]") {
  const Case c = test::load_case("shock", {parse_set_option("init.method=structured")});
  const Outcome host = test::run_case(c, 100, false);
  for (const ocl::ForceLoop loop : test::kForceLoops) {
    INFO(ocl::force_loop_name(loop) << " force loop");
    const Outcome dev = test::run_case(c, 100, true, false, 0.3, loop);
    CHECK(dev.stats.snap_rebuilds > 0);
    require_identical_nodes(host.nodes, dev.nodes);
    CHECK(dev.result.stats.snapped == host.result.stats.snapped);
  }
}

// Snaps the skin rule would not rebuild for, at random: from the structured start of circle_circle
// (small moves), in phases of a few iterations; before each phase random interior nodes near a circle
// are put just outside the domain (they snap in the phase's first iteration), and both runs continue
// from the same SimState (the resume path). Random skins, stability settings and nodes, from a fixed
// seed (each trial's settings are printed on failure); the trials alternate the two force loops.
TEST_CASE("device run: randomized snap stress stays bit-identical to the host", "[opencl][device_sim]") {
  const Case c = test::load_case("circle_circle");
  std::mt19937_64 rng(20240613);
  int forced = 0;
  std::size_t snaps = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const ocl::ForceLoop loop = test::kForceLoops[trial % 2];
    SimOptions o = test::options_for(c, 0);
    o.verlet_skin = 1.0 + 2.0 * pdmesh_test::uniform(rng);
    o.stability_factor = rng() % 2 == 0 ? 1.0 : 0.0;
    INFO("trial " << trial << ": skin " << o.verlet_skin << ", stability factor " << o.stability_factor << ", "
                  << ocl::force_loop_name(loop) << " force loop");
    NodeSet host_nodes = c.initial, dev_nodes = c.initial;
    SimState host_state, dev_state;
    for (int phase = 0; phase < 4; ++phase) {
      INFO("phase " << phase);
      // Outer circle r = 10 (its polygon lies inside it), inner r = 0.5 (its chords at 0.49966).
      for (int moved = 0; moved < 8;) {
        const std::size_t i = rng() % c.initial.size();
        if (host_nodes.kind[i] != NodeKind::Interior) continue;
        const double r = norm(host_nodes.x[i]), q = host_nodes.q[i];
        const double nudge = 1e-3 * q * (1.0 + 9.0 * pdmesh_test::uniform(rng));
        double to = 0.0;
        if (r > 10.0 - 2.0 * q)
          to = 10.0 + nudge;
        else if (r < 0.5 + 2.0 * q)
          to = 0.499 - nudge;
        else
          continue;
        host_nodes.x[i] = dev_nodes.x[i] = host_nodes.x[i] * (to / r);
        ++moved;
      }
      o.iterations = 8 * (phase + 1);
      o.resume = phase == 0 ? nullptr : &host_state;
      test::Outcome host = test::run_from(c, host_nodes, o, false);
      o.resume = phase == 0 ? nullptr : &dev_state;
      test::Outcome dev = test::run_from(c, dev_nodes, o, true, false, loop);
      require_identical_nodes(host.nodes, dev.nodes);
      REQUIRE(dev.result.history.size() == host.result.history.size());
      for (std::size_t k = 0; k < host.result.history.size(); ++k)
        CHECK(dev.result.history[k].snapped == host.result.history[k].snapped);
      forced += dev.stats.snap_rebuilds;
      snaps += dev.result.stats.snapped;
      host_nodes = host.nodes;
      dev_nodes = dev.nodes;
      host_state = host.result.state;
      dev_state = dev.result.state;
    }
  }
  // The stress did what it is for: snaps, and rebuilds that only a snap asked for.
  CHECK(snaps > 0);
  CHECK(forced > 0);
}

namespace {

// circle_circle from a random start (vacancies and clusters), population events every 10 iterations
// from `start` on.
Case circle_circle_with_population(const char* start) {
  Case c;
  c.config = load_case_file(pdmesh::test::source_dir() + "/cases/circle_circle/case.toml",
                            {{"init.method", "random", "test"},
                             {"population.enabled", "true", "test"},
                             {"population.start", start, "test"},
                             {"population.every", "10", "test"}});
  c.config.quiet = true;
  c.inputs = std::make_unique<MeshInputs>(c.config);
  c.spacing = std::make_unique<SpacingStage>(c.config, *c.inputs, SpacingStage::Build::FieldOnly);
  c.initial = make_initial(c.config, *c.inputs, *c.spacing).nodes;
  return c;
}

// 100 iterations of the case with its population control, on the host reference or the device (double).
Outcome run_with_population(const Case& c, bool device) {
  Outcome out{c.initial, {}, {}};
  SimOptions o = options_for(c, 100);
  o.population = c.config.population;
  if (device) {
    out.result = ocl::run_device_simulation(out.nodes, *c.inputs->tree, *c.inputs->spacing, o, test::test_context(),
                                            ocl::Precision::Double, {}, &out.stats);
  } else {
    out.result = run_simulation(out.nodes, *c.inputs->tree, *c.inputs->spacing, o);
  }
  return out;
}

}  // namespace

TEST_CASE("device run with population control: same node changes as the host", "[opencl][device_sim][population]") {
  // circle_circle from a random start (vacancies and clusters), events after 20, 30, ... 80 (the last
  // one at floor(0.8 x 100)). In double bit for bit (the device re-uploads the host's edited node set
  // exactly); the same inserted/removed counts per iteration and the same node count and kinds.
  const Case c = circle_circle_with_population("20");
  const Outcome host = run_with_population(c, false), dev = run_with_population(c, true);
  REQUIRE(host.result.stats.inserted + host.result.stats.removed > 0);
  CHECK(dev.result.stats.inserted == host.result.stats.inserted);
  CHECK(dev.result.stats.removed == host.result.stats.removed);
  CHECK(dev.result.stats.population_events == host.result.stats.population_events);
  REQUIRE(dev.result.history.size() == host.result.history.size());
  for (std::size_t k = 0; k < host.result.history.size(); ++k) {
    CHECK(dev.result.history[k].inserted == host.result.history[k].inserted);
    CHECK(dev.result.history[k].removed == host.result.history[k].removed);
    CHECK(dev.result.history[k].interior == host.result.history[k].interior);
  }
  require_identical_nodes(host.nodes, dev.nodes);
  CHECK(dev.result.state.population.last_event == 80);
  CHECK(dev.stats.population_seconds > 0.0);
  // The timings file's split of the device run carries its population events' time; the host has none.
  CHECK(host.result.stats.split.empty());
  const auto& split = dev.result.stats.split;
  const auto named = std::find_if(split.begin(), split.end(),
                                  [](const auto& entry) { return entry.first == "device_population_seconds"; });
  REQUIRE(named != split.end());
  CHECK(named->second == dev.stats.population_seconds);
}

TEST_CASE("device run whose population control settles early: same events and nodes as the host",
          "[opencl][device_sim][population]") {
  // settle = 0.1: every event is quiet, so after the events of iterations 20 and 40 (the interval
  // doubles) population control is over: no event at 80 (the last one otherwise), on both.
  Case c = circle_circle_with_population("20");
  c.config.population.settle = 0.1;
  c.config.population.settle_events = 2;
  const Outcome host = run_with_population(c, false), dev = run_with_population(c, true);
  CHECK(host.result.stats.population_events == 2);
  CHECK(dev.result.stats.population_events == 2);
  CHECK(host.result.state.population.last_event == 40);
  CHECK(dev.result.state.population.last_event == 40);
  CHECK(dev.result.state.population.finished(c.config.population));
  CHECK(dev.result.stats.inserted == host.result.stats.inserted);
  CHECK(dev.result.stats.removed == host.result.stats.removed);
  require_identical_nodes(host.nodes, dev.nodes);
}

// Builds without counts (the run's first, and after every population event) laid out from a sampled
// estimate (forced on this small case: PDMESH_TEST_SAMPLE_STRIDE; from 65536 nodes by default): rows
// above their level's estimate move behind the others, and the run stays the host's bit for bit.
TEST_CASE("device run with rows from a sampled estimate is bit-identical to the host",
          "[opencl][device_sim][population]") {
  const Case c = circle_circle_with_population("10");
  SimOptions o = options_for(c, 40);
  o.population = c.config.population;
  NodeSet host_nodes = c.initial, dev_nodes = c.initial;
  const SimResult host = run_simulation(host_nodes, *c.inputs->tree, *c.inputs->spacing, o);
  for (const ocl::ForceLoop loop : test::kForceLoops) {
    INFO(ocl::force_loop_name(loop) << " force loop");
    dev_nodes = c.initial;
    ocl::DeviceRunStats stats;
    ::setenv("PDMESH_TEST_SAMPLE_STRIDE", "4", 1);
    const SimResult dev = ocl::run_device_simulation(dev_nodes, *c.inputs->tree, *c.inputs->spacing, o,
                                                     test::test_context(), ocl::Precision::Double, {}, &stats, loop);
    ::unsetenv("PDMESH_TEST_SAMPLE_STRIDE");
    REQUIRE(host.stats.population_events > 0);
    // The first build samples; after each event the last counts are carried over to the renumbered
    // nodes (DeviceNeighbours::carry_counts), so no later build samples or counts first.
    CHECK(stats.sampled_builds == 1);
    CHECK(stats.outgrown_rows > 0);  // the estimate left rows to move
    REQUIRE(dev.history.size() == host.history.size());
    for (std::size_t k = 0; k < host.history.size(); ++k) {
      INFO("iteration " << host.history[k].iteration);
      CHECK(dev.history[k].max_force == host.history[k].max_force);
      CHECK(dev.history[k].dt_gm == host.history[k].dt_gm);
      CHECK(dev.history[k].interior == host.history[k].interior);
    }
    CHECK(dev.stats.pairs_within == host.stats.pairs_within);
    require_identical_nodes(host_nodes, dev_nodes);
  }
}

TEST_CASE(
    "device run: the convergence rule stops a double run after the host's iteration, with the host's "
    "measurements",
    "[opencl][device_sim][convergence]") {
  // circle_circle with a short rule (measured every 20 iterations, window 60) so that it converges
  // within a few hundred iterations; in double the device repeats the host bit for bit, so the
  // measurements and the stop must be the same.
  const Case c = test::load_case("circle_circle", {parse_set_option("simulation.stop=converged")});
  SimOptions o = options_for(c, 600);
  o.convergence = simulation_options(c.config).convergence;
  REQUIRE(o.convergence.enabled);
  o.convergence.check_every = 20;
  o.convergence.window = 60;
  o.convergence.min_iterations = 100;
  const Outcome host = test::run_from(c, c.initial, o, false);
  const Outcome dev = test::run_from(c, c.initial, o, true);
  REQUIRE(host.result.converged);
  CHECK(dev.result.converged);
  CHECK(dev.result.state.iterations_done == host.result.state.iterations_done);
  INFO("the host run converged after " << host.result.state.iterations_done);
  CHECK(host.result.state.iterations_done < 600);
  const auto& hs = host.result.state.convergence;
  const auto& ds = dev.result.state.convergence;
  REQUIRE(ds.size() == hs.size());
  for (std::size_t k = 0; k < hs.size(); ++k) {
    INFO("measurement after iteration " << hs[k].iteration);
    CHECK(ds[k].iteration == hs[k].iteration);
    CHECK(ds[k].min_angle == hs[k].min_angle);
    CHECK(ds[k].aspect_ratio == hs[k].aspect_ratio);
  }
  require_identical_nodes(host.nodes, dev.nodes);
  // The last measurement's mesh comes back for the mesh stage: the final nodes' triangulation.
  REQUIRE(dev.result.final_mesh);
  CHECK(triangulates(*dev.result.final_mesh, dev.nodes));
  CHECK(dev.result.final_mesh->triangles == triangulate(dev.nodes, c.inputs->curve_names()).triangles);
}

TEST_CASE("device run in float stays close to the host for 10 iterations", "[opencl][device_sim]") {
  const Case c = test::load_case("circle_circle");
  const Outcome host = test::run_case(c, 10, false);
  for (const ocl::ForceLoop loop : test::kForceLoops) {
    INFO(ocl::force_loop_name(loop) << " force loop");
    const Outcome dev = test::run_case(c, 10, true, true, 0.3, loop);
    require_same_nodes(host.nodes, dev.nodes, 2e-2);
  }
}

TEST_CASE("device run: a whole circle_circle run gives the host's mesh quality", "[opencl][device_sim]") {
  // 300 iterations (the settled regime starts at ~120; 2000 would take minutes on CI's 2 cores).
  const Case c = test::load_case("circle_circle");
  const Outcome host = test::run_case(c, 300, false);
  const Outcome dev = test::run_case(c, 300, true);
  const auto names = c.inputs->curve_names();
  const QualitySummary qh = summarize_quality(triangulate(host.nodes, names));
  const QualitySummary qd = summarize_quality(triangulate(dev.nodes, names));
  CHECK(qd.triangles == qh.triangles);
  CHECK(std::fabs(qd.min_angle - qh.min_angle) <= 0.5);
  CHECK(qd.aspect_ratio_avg == Approx(qh.aspect_ratio_avg).epsilon(0.01));
  CHECK(dev.result.stats.snapped == host.result.stats.snapped);
  // The Verlet skin: lists are rebuilt far less often than every iteration (measured: 23 of 300).
  CHECK(dev.stats.rebuilds < 100);
}

// The rows hold every pair the step's forces take, before every step of whole runs (PDMESH_TEST_CHECK_ROWS:
// the reference's exact rows at the state the step reads, else the run throws): the Verlet skin's
// rebuild trigger is safe (host/opencl/device_run.hpp). Runs that keep their rows for many iterations,
// where the nodes move fast: from a random start, whose nodes close its gaps from both sides, with
// momentum and population events (circle_circle), and the graded spacing of an airfoil, whose nodes
// have skin classes above 0 (naca0012).
TEST_CASE("device run: the rows hold every pair within the cut-off before every step", "[opencl][device_sim]") {
  const pdmesh_test::ScopedEnv check("PDMESH_TEST_CHECK_ROWS", "1");
  struct Run {
    const char* name;
    Case c;
    int iterations;
    double momentum, skin;
  };
  const Run runs[] = {
      {"circle_circle, thesis options", test::load_case("circle_circle"), 300, 0.0, 0.3},
      {"circle_circle, random start, thesis options",
       test::load_case("circle_circle", {{"init.method", "random", "test"}}), 100, 0.0, 0.3},
      {"circle_circle, random start, momentum, population",
       test::load_case("circle_circle", {{"init.method", "random", "test"},
                                         {"population.enabled", "true", "test"},
                                         {"population.start", "20", "test"},
                                         {"population.every", "10", "test"}}),
       200, 0.9, 0.6},
      {"naca0012, momentum", test::load_case("naca0012"), 150, 0.9, 0.6},
  };
  for (const Run& r : runs) {
    INFO(r.name);
    SimOptions o = options_for(r.c, r.iterations);
    o.population = r.c.config.population;
    o.momentum = r.momentum;
    o.verlet_skin = r.skin;
    Outcome dev;
    REQUIRE_NOTHROW(dev = test::run_from(r.c, r.c.initial, o, true));
    CHECK(dev.stats.iterations == r.iterations);
    // The rows were kept across iterations (the test's point): built far less often than every iteration.
    INFO(dev.stats.rebuilds << " builds");
    CHECK(4 * dev.stats.rebuilds < dev.stats.iterations);
  }
}

TEST_CASE("device run refuses the exact spacing field", "[opencl][device_sim]") {
  const Case c = test::load_case("circle_circle");
  NodeSet nodes = c.initial;
  SimOptions o = options_for(c, 1);
  o.exact_spacing = true;
  REQUIRE_THROWS_AS(ocl::run_device_simulation(nodes, *c.inputs->tree, *c.inputs->spacing, o, test::test_context()),
                    InputError);
}

// The window's length is bounded by SimOptions::window_seconds at the last window's pace (so that a stop
// request waits little at any size), and the length does not change the result: windows of one
// iteration (a bound far below any iteration's time) give the host's nodes and history bit for bit, as
// whole windows do.
TEST_CASE("device run: windows bounded in time give the same run", "[opencl][device_sim]") {
  const Case c = test::load_case("naca0012");
  SimOptions o = test::options_for(c, 120);
  const test::Outcome host = test::run_from(c, c.initial, o, false);
  const test::Outcome whole = test::run_from(c, c.initial, o, true);
  o.window_seconds = 1e-12;
  const test::Outcome short_windows = test::run_from(c, c.initial, o, true);
  CHECK(short_windows.stats.windows > 2 * whole.stats.windows);
  CHECK(short_windows.stats.windows >= 80);  // one iteration each after the first window
  require_identical_nodes(host.nodes, whole.nodes);
  require_identical_nodes(host.nodes, short_windows.nodes);
  REQUIRE(short_windows.result.history.size() == host.result.history.size());
  for (std::size_t k = 0; k < host.result.history.size(); ++k) {
    INFO("iteration " << k + 1);
    CHECK(short_windows.result.history[k].dt_gm == host.result.history[k].dt_gm);
    CHECK(short_windows.result.history[k].snapped == host.result.history[k].snapped);
  }
}
