// The convergence stopping rule (sim/convergence): the monitor on synthetic measurement sequences
// whose convergence iteration is known, its options' validation, measure_mesh on small node sets, and
// the rule inside the host driver: a run that converges stops there, and a run stopped (also in a
// measured iteration) and resumed from its checkpoint stops where the uninterrupted run did.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "mesh/metric_quality.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "sim/checkpoint.hpp"
#include "sim/convergence.hpp"
#include "sim/simulation.hpp"
#include "convergence_fixtures.hpp"
#include "seeded_random.hpp"

using namespace pdmesh;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ConvergenceOptions small_options() { return pdmesh_test::small_convergence_options(); }

// A mesh that improves until iteration 60 (aspect ratio falling by 0.01 and the smallest angle rising
// by 1 degree per measurement) and then only wobbles within the tolerances.
MeshSample settling(int iteration) {
  if (iteration <= 60) return {iteration, 20.0 + iteration / 10.0, 1.10 - iteration / 1000.0};
  const double wobble = (iteration / 10) % 2 == 0 ? 1.0 : -1.0;
  return {iteration, 26.0 + 0.1 * wobble, 1.04 + 1e-4 * wobble};
}

// Feeds iterations 1 .. last to `monitor` (a sample at every due iteration from `sample`) and returns
// the first iteration it reports converged, or 0.
int first_converged(
    ConvergenceMonitor& monitor, int last, const std::function<MeshSample(int)>& sample,
    const std::function<bool(int)>& settled = [](int) { return true; }, int from = 1) {
  for (int it = from; it <= last; ++it) {
    HistoryRow row;
    row.iteration = it;
    std::optional<MeshSample> s;
    if (monitor.due(it)) s = sample(it);
    if (monitor.observe(row, s ? &*s : nullptr, settled(it))) return it;
  }
  return 0;
}

}  // namespace

TEST_CASE("convergence: a mesh that settles at iteration 60 converges one window later, at 100", "[convergence]") {
  ConvergenceMonitor monitor(small_options());
  CHECK_FALSE(monitor.due(0));
  CHECK_FALSE(monitor.due(5));
  CHECK(monitor.due(10));
  CHECK(first_converged(monitor, 300, settling) == 100);
  // Every measurement up to the stop was kept (for the checkpoint), one per check.
  REQUIRE(monitor.samples().size() == 10);
  CHECK(monitor.samples().back().iteration == 100);
  CHECK(monitor.converged_after(100));
  CHECK_FALSE(monitor.converged_after(95));  // between measurements: never
}

TEST_CASE("convergence: never before min_iterations, and never while disabled", "[convergence]") {
  ConvergenceOptions o = small_options();
  o.min_iterations = 150;
  ConvergenceMonitor late(o);
  CHECK(first_converged(late, 300, settling) == 150);
  o.enabled = false;
  ConvergenceMonitor off(o);
  CHECK_FALSE(off.due(100));
  CHECK(first_converged(off, 300, settling) == 0);
  CHECK(off.samples().empty());
}

TEST_CASE("convergence: never while population control may still change the node set", "[convergence]") {
  ConvergenceMonitor monitor(small_options());
  // Unsettled until iteration 125: the first measurement after that, 130, stops the run; the
  // measurements taken meanwhile count for the window.
  CHECK(first_converged(monitor, 300, settling, [](int it) { return it >= 125; }) == 130);
  CHECK(monitor.samples().size() == 13);
  ConvergenceMonitor never(small_options());
  CHECK(first_converged(never, 300, settling, [](int) { return false; }) == 0);
}

TEST_CASE("convergence: a mesh that keeps improving or drifting does not converge", "[convergence]") {
  // The smallest angle reaches a new best by more than the tolerance at every measurement.
  ConvergenceMonitor rising(small_options());
  CHECK(first_converged(rising, 400, [](int it) { return MeshSample{it, 10.0 + 0.03 * it, 1.05}; }) == 0);
  // The average aspect ratio drifts by 2e-5 per iteration: 8e-4 over the window, above 5e-4.
  ConvergenceMonitor drifting(small_options());
  CHECK(first_converged(drifting, 400, [](int it) { return MeshSample{it, 30.0, 1.05 - 2e-5 * it}; }) == 0);
  // The smallest angle falling (a worse mesh) is not a new best: the aspect ratio decides alone, as
  // early as it can: the window needs a measurement at its start (none at iteration 0), so 50.
  ConvergenceMonitor falling(small_options());
  CHECK(first_converged(falling, 400, [](int it) { return MeshSample{it, 30.0 - 0.01 * it, 1.05}; }) == 50);
}

TEST_CASE("convergence: NaN measurements (nodes that did not triangulate) never converge", "[convergence]") {
  // One NaN at iteration 80: no window that holds it (up to 120) converges; 130 does.
  ConvergenceMonitor one(small_options());
  const auto with_hole = [](int it) { return it == 80 ? MeshSample{it, kNaN, kNaN} : settling(it); };
  CHECK(first_converged(one, 300, with_hole) == 130);
  ConvergenceMonitor all(small_options());
  CHECK(first_converged(all, 300, [](int it) { return MeshSample{it, kNaN, kNaN}; }) == 0);
  // NaN in the angle alone counts as well.
  ConvergenceMonitor angle(small_options());
  CHECK(first_converged(angle, 300, [](int it) { return MeshSample{it, kNaN, 1.05}; }) == 0);
}

TEST_CASE("convergence: a monitor given the earlier measurements continues as the uninterrupted one", "[convergence]") {
  ConvergenceMonitor whole(small_options());
  const int stop = first_converged(whole, 300, settling);
  REQUIRE(stop == 100);
  for (const int cut : {50, 70, 99}) {
    INFO("cut after iteration " << cut);
    ConvergenceMonitor first(small_options());
    REQUIRE(first_converged(first, cut, settling) == 0);
    ConvergenceMonitor second(small_options(), first.samples());
    CHECK(first_converged(
              second, 300, settling, [](int) { return true; }, cut + 1) == stop);
  }
  // Cut exactly where it converged: the measurements alone say so.
  ConvergenceMonitor first(small_options());
  REQUIRE(first_converged(first, 100, settling) == 100);
  const ConvergenceMonitor second(small_options(), first.samples());
  CHECK(second.converged_after(100));
  CHECK_FALSE(second.converged_after(100, false));
}

TEST_CASE("convergence options: invalid values are refused naming the option", "[convergence]") {
  const auto refused = [](const std::function<void(ConvergenceOptions&)>& change, const std::string& words) {
    ConvergenceOptions o = small_options();
    change(o);
    CHECK_THROWS_AS(check_convergence_options(o), InputError);
    CHECK_THROWS_WITH(check_convergence_options(o), Catch::Contains(words));
    CHECK_THROWS_AS(ConvergenceMonitor(o), InputError);
  };
  CHECK_NOTHROW(check_convergence_options(small_options()));
  CHECK_NOTHROW(check_convergence_options(ConvergenceOptions{}));  // the defaults
  refused([](ConvergenceOptions& o) { o.check_every = 0; }, "check_every must be >= 1");
  refused([](ConvergenceOptions& o) { o.window = 5; }, "window must be a positive multiple of check_every");
  refused([](ConvergenceOptions& o) { o.window = 45; }, "window must be a positive multiple of check_every");
  refused([](ConvergenceOptions& o) { o.aspect_tolerance = -1e-4; }, "aspect tolerance");
  refused([](ConvergenceOptions& o) { o.aspect_tolerance = kNaN; }, "aspect tolerance");
  refused([](ConvergenceOptions& o) { o.angle_tolerance = HUGE_VAL; }, "angle tolerance");
  refused([](ConvergenceOptions& o) { o.min_iterations = -1; }, "min_iterations");
}

TEST_CASE(
    "measure_mesh: the triangulated nodes' smallest angle and mean aspect ratio, NaN when they do not "
    "triangulate",
    "[convergence]") {
  // A unit square of four corners and one interior node off centre.
  NodeSet nodes;
  const Vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k) nodes.add(corners[k], 0.5, NodeKind::Fixed, k);
  nodes.add({0.4, 0.45}, 0.5, NodeKind::Interior, -1);
  nodes.curve_nodes = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  std::vector<std::array<int, 3>> triangles;
  const MeshSample s = measure_mesh(nodes, 7, &triangles);
  CHECK(s.iteration == 7);
  const Mesh direct = triangulate(nodes, {"c0", "c1", "c2", "c3"});
  const QualitySummary q = summarize_quality(direct);
  // The triangles it measured, handed out, make triangulate's mesh, recognised as these nodes' mesh.
  CHECK(triangles == direct.triangles);
  const Mesh kept = measured_mesh(nodes, triangles);
  CHECK(kept.triangles == direct.triangles);
  CHECK(kept.boundary_edges.size() == direct.boundary_edges.size());
  CHECK(kept.kind == direct.kind);
  CHECK(kept.points == direct.points);
  CHECK(kept.curve_names == direct.curve_names);
  CHECK(triangulates(kept, nodes));
  {
    NodeSet moved = nodes;
    moved.x[4].x = std::nextafter(moved.x[4].x, 1.0);  // one ulp
    CHECK_FALSE(triangulates(kept, moved));
    NodeSet rekinded = nodes;
    rekinded.kind[4] = NodeKind::Boundary;
    CHECK_FALSE(triangulates(kept, rekinded));
    NodeSet rechained = nodes;
    rechained.curve_nodes = {{0, 1}, {1, 2}, {2, 3, 0}};
    CHECK_FALSE(triangulates(kept, rechained));
    NodeSet shorter = nodes;
    shorter.curve_nodes.back() = {3};
    CHECK_FALSE(triangulates(kept, shorter));
  }
  REQUIRE(q.triangles == 4);
  CHECK(s.min_angle == Approx(q.min_angle).epsilon(1e-12));
  CHECK(s.aspect_ratio == Approx(q.aspect_ratio_avg).epsilon(1e-12));
  // A second interior node on top of the first: no triangulation, NaN values (not an exception).
  nodes.add({0.4, 0.45}, 0.5, NodeKind::Interior, -1);
  const MeshSample bad = measure_mesh(nodes, 8, &triangles);
  CHECK(std::isnan(bad.min_angle));
  CHECK(std::isnan(bad.aspect_ratio));
  CHECK(triangles == direct.triangles);  // left as they were
}

TEST_CASE("canonical_order: one order for a set of triangles, however laid out and rotated", "[convergence]") {
  std::mt19937_64 rng(5);
  std::vector<Vec2> pts;
  for (int k = 0; k < 500; ++k) pts.push_back({pdmesh_test::unit(rng), pdmesh_test::unit(rng)});
  const std::vector<std::array<int, 3>> tris = Triangulation(pts).inner_triangles();
  const auto canonical = [&](const std::vector<std::array<int, 3>>& list) {
    std::vector<std::array<int, 3>> out;
    for (const std::uint32_t k : canonical_order(list, pts.size())) {
      std::array<int, 3> t = list[k];
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      out.push_back(t);
    }
    return out;
  };
  const std::vector<std::array<int, 3>> first = canonical(tris);
  REQUIRE(first.size() == tris.size());
  for (std::size_t k = 1; k < first.size(); ++k) CHECK(first[k - 1] < first[k]);  // sorted, no repeat
  std::vector<std::array<int, 3>> shuffled = tris;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  for (auto& t : shuffled) std::rotate(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(rng() % 3), t.end());
  CHECK(canonical(shuffled) == first);
}

TEST_CASE("measure_mesh from a population event's triangulation: the same sample, no triangles handed out",
          "[convergence]") {
  // A square boundary dense enough that its edges are Delaunay, random interior nodes, then 20 more
  // appended (as an event's insertions).
  NodeSet nodes;
  const int side = 40;
  for (int k = 0; k < 4 * side; ++k) {
    const double t = static_cast<double>(k % side) / side;
    const Vec2 p = k < side ? Vec2{t, 0} : k < 2 * side ? Vec2{1, t} : k < 3 * side ? Vec2{1 - t, 1} : Vec2{0, 1 - t};
    nodes.add(p, 0.1, NodeKind::Boundary, 0);
  }
  std::vector<int> loop(4 * side);
  for (int k = 0; k < 4 * side; ++k) loop[static_cast<std::size_t>(k)] = k;
  loop.push_back(0);
  nodes.curve_nodes = {loop};
  std::mt19937_64 rng(8);
  const auto add = [&](int count) {
    for (int k = 0; k < count; ++k)
      nodes.add({0.02 + 0.96 * pdmesh_test::unit(rng), 0.02 + 0.96 * pdmesh_test::unit(rng)}, 0.1, NodeKind::Interior,
                -1);
  };
  add(600);
  const std::vector<Vec2> before = nodes.x;
  add(20);
  std::vector<std::array<int, 3>> scratch_triangles;
  const MeshSample scratch = measure_mesh(nodes, 3, &scratch_triangles);
  REQUIRE(std::isfinite(scratch.aspect_ratio));
  REQUIRE_FALSE(scratch_triangles.empty());
  std::optional<Triangulation> start(Triangulation{before});
  std::vector<std::array<int, 3>> triangles;
  const MeshSample s = measure_mesh(nodes, 3, &triangles, &start);
  CHECK_FALSE(start.has_value());  // taken
  CHECK(triangles.empty());        // not triangulate_triangles' order: none handed out
  // Bit for bit.
  CHECK(std::memcmp(&s.aspect_ratio, &scratch.aspect_ratio, sizeof(double)) == 0);
  CHECK(std::memcmp(&s.min_angle, &scratch.min_angle, sizeof(double)) == 0);
  // A start that is not the nodes' (one moved by an ulp): from scratch, with the triangles.
  std::vector<Vec2> moved = before;
  moved[300].y = std::nextafter(moved[300].y, 2.0);
  start.emplace(moved);
  const MeshSample again = measure_mesh(nodes, 3, &triangles, &start);
  CHECK_FALSE(start.has_value());
  CHECK(triangles == scratch_triangles);
  CHECK(std::memcmp(&again.aspect_ratio, &scratch.aspect_ratio, sizeof(double)) == 0);
}

namespace {

// circle_circle (thesis preset) from its structured start on the host, with a short rule so that the
// run converges within a few hundred iterations.
struct SmallRun {
  CaseConfig config;
  std::unique_ptr<MeshInputs> inputs;
  std::unique_ptr<SpacingStage> spacing;
  NodeSet initial;
  SimOptions options;

  SmallRun() {
    config = load_case_file(std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle/case.toml",
                            {{"simulation.stop", "converged", "test"}, {"simulation.iterations", "600", "test"}});
    config.quiet = true;
    inputs = std::make_unique<MeshInputs>(config);
    spacing = std::make_unique<SpacingStage>(config, *inputs);
    initial = make_initial(config, *inputs, *spacing).nodes;
    options = simulation_options(config);
    options.background = &spacing->background();  // as the mesh command passes it
    options.convergence.check_every = 20;
    options.convergence.window = 60;
    options.convergence.min_iterations = 100;
  }
  SimResult run(NodeSet& nodes, const SimState* resume = nullptr, const std::atomic<bool>* stop = nullptr) const {
    SimOptions o = options;
    o.resume = resume;
    o.stop = stop;
    return run_simulation(nodes, *inputs->tree, spacing->field(), o);
  }
};

}  // namespace

TEST_CASE("convergence in the host driver: the run stops at a measurement, and a resumed run stops there too",
          "[convergence][sim][resume]") {
  const SmallRun c;
  REQUIRE(c.options.convergence.enabled);  // simulation.stop = "converged"
  NodeSet whole = c.initial;
  const SimResult full = c.run(whole);
  REQUIRE(full.converged);
  const int stop = full.state.iterations_done;
  INFO("converged after " << stop);
  CHECK(stop % c.options.convergence.check_every == 0);
  CHECK(stop >= c.options.convergence.min_iterations);
  CHECK(stop < 600);
  CHECK(full.history.size() == static_cast<std::size_t>(stop));
  CHECK(full.state.convergence.size() == static_cast<std::size_t>(stop / c.options.convergence.check_every));
  // The timings file's split counts every measurement this run took, and times them.
  CHECK(full.stats.measurements == stop / c.options.convergence.check_every);
  CHECK(full.stats.measure_seconds > 0.0);
  CHECK(full.stats.measure_cpu_seconds > 0.0);
  // The host driver has nothing to do before a measurement: its wait is a small part of it.
  CHECK(full.stats.measure_wait_seconds >= 0.0);
  CHECK(full.stats.measure_wait_seconds < full.stats.measure_seconds);
  // The last measurement's mesh, for the mesh stage: the final nodes' triangulation.
  REQUIRE(full.final_mesh);
  CHECK(triangulates(*full.final_mesh, whole));
  CHECK(full.final_mesh->triangles == triangulate(whole, c.inputs->curve_names()).triangles);

  // Stopped after a measured iteration (its measurement must reach the resumed run), after one between
  // measurements, and after the very iteration it converged in; the state goes through the checkpoint
  // file format, as with --stop-after and --resume.
  for (const int cut : {80, stop - 7, stop}) {
    INFO("stopped after iteration " << cut);
    NodeSet nodes = c.initial;
    std::atomic<bool> flag{false};
    SimOptions first_options = c.options;
    first_options.stop = &flag;
    SimCallbacks callbacks;
    callbacks.on_iteration = [&](const HistoryRow& row) {
      if (row.iteration == cut) flag = true;
    };
    const SimResult part = run_simulation(nodes, *c.inputs->tree, c.spacing->field(), first_options, callbacks);
    REQUIRE(part.state.iterations_done == cut);
    CHECK(part.stopped == (cut != stop));
    CHECK(part.converged == (cut == stop));
    CHECK(static_cast<bool>(part.final_mesh) == (cut == stop));  // only a converged run hands one out
    const Checkpoint saved = parse_checkpoint(format_checkpoint(Checkpoint{{}, nodes, part.state}), "mem");
    REQUIRE(saved.state.convergence.size() == part.state.convergence.size());
    NodeSet resumed_nodes = saved.nodes;
    const SimResult resumed = c.run(resumed_nodes, &saved.state);
    CHECK(resumed.converged);
    CHECK(resumed.state.iterations_done == stop);
    CHECK(resumed.history.size() == full.history.size());
    CHECK(resumed_nodes.x == whole.x);
    REQUIRE(resumed.state.convergence.size() == full.state.convergence.size());
    for (std::size_t k = 0; k < full.state.convergence.size(); ++k) {
      CHECK(resumed.state.convergence[k].iteration == full.state.convergence[k].iteration);
      CHECK(resumed.state.convergence[k].min_angle == full.state.convergence[k].min_angle);
      CHECK(resumed.state.convergence[k].aspect_ratio == full.state.convergence[k].aspect_ratio);
    }
  }
}

TEST_CASE("convergence off (simulation.stop = iterations): every iteration runs, nothing is measured",
          "[convergence][sim]") {
  SmallRun c;
  c.options.convergence.enabled = false;
  c.options.iterations = 150;
  NodeSet nodes = c.initial;
  const SimResult r = c.run(nodes);
  CHECK_FALSE(r.converged);
  CHECK(r.state.iterations_done == 150);
  CHECK(r.state.convergence.empty());
  CHECK(r.stats.measurements == 0);
  CHECK(r.stats.measure_seconds == 0.0);
  CHECK(r.stats.measure_wait_seconds == 0.0);
}

TEST_CASE("convergence: a run that did not converge says which part of the rule held it", "[convergence]") {
  const ConvergenceOptions o = small_options();
  SECTION("the aspect ratio still changing") {
    std::vector<MeshSample> samples;
    for (int it = 10; it <= 80; it += 10) samples.push_back({it, 30.0, 1.10 - it / 1000.0});
    const ConvergenceMonitor m(o, samples);
    CHECK_FALSE(m.converged_after(80));
    CHECK(m.not_converged_reason(80) ==
          "the mean aspect ratio of the triangulated nodes changed by 0.04 over iterations 40-80 (tolerance 0.0005)");
  }
  SECTION("a new best smallest angle") {
    std::vector<MeshSample> samples;
    for (int it = 10; it <= 80; it += 10) samples.push_back({it, 20.0 + it / 10.0, 1.04});
    const ConvergenceMonitor m(o, samples);
    CHECK(
        m.not_converged_reason(80) ==
        "the smallest angle reached a new best over iterations 40-80: 28.00 deg against 24.00 before (tolerance 0.25)");
  }
  SECTION("settled, early, unsettled population, no window") {
    std::vector<MeshSample> samples;
    for (int it = 10; it <= 100; it += 10) samples.push_back(settling(it));
    const ConvergenceMonitor m(o, samples);
    CHECK(m.converged_after(100));
    CHECK(m.not_converged_reason(100).empty());
    CHECK(m.not_converged_reason(100, false) == "population control had not settled");
    CHECK(m.not_converged_reason(30) == "iteration 30 is before the earliest stop (40)");
    CHECK(m.not_converged_reason(95) == "no measured window of 40 iterations ends at iteration 95");
    std::vector<MeshSample> bad = samples;
    bad[8].min_angle = kNaN;  // iteration 90
    CHECK(ConvergenceMonitor(o, bad).not_converged_reason(100) ==
          "the nodes did not triangulate at a measurement after iteration 60");
  }
}

TEST_CASE("simulation_options: the stop tolerances and population settling keys reach the drivers", "[convergence]") {
  const CaseConfig config = load_case_file(std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle/case.toml",
                                           {{"simulation.stop_aspect", "1e-3", "test"},
                                            {"simulation.stop_angle", "0.5", "test"},
                                            {"population.settle", "2e-3", "test"},
                                            {"population.settle_events", "3", "test"}});
  const SimOptions o = simulation_options(config);
  CHECK(o.convergence.aspect_tolerance == 1e-3);
  CHECK(o.convergence.angle_tolerance == 0.5);
  CHECK(o.population.settle == 2e-3);
  CHECK(o.population.settle_events == 3);
  const SimOptions r = simulation_options(load_case_file(
      std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle/case.toml", {{"simulation.stop_every", "50", "test"},
                                                                          {"simulation.stop_window", "200", "test"},
                                                                          {"simulation.stop_min", "300", "test"}}));
  CHECK(r.convergence.check_every == 50);
  CHECK(r.convergence.window == 200);
  CHECK(r.convergence.min_iterations == 300);
  // The defaults are the rule's own.
  const SimOptions d =
      simulation_options(load_case_file(std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle/case.toml"));
  CHECK(d.convergence.aspect_tolerance == ConvergenceOptions{}.aspect_tolerance);
  CHECK(d.convergence.angle_tolerance == ConvergenceOptions{}.angle_tolerance);
  CHECK(d.convergence.check_every == ConvergenceOptions{}.check_every);
  CHECK(d.convergence.window == ConvergenceOptions{}.window);
  CHECK(d.convergence.min_iterations == ConvergenceOptions{}.min_iterations);
}

TEST_CASE("the best preset converges a geometry alone in a fraction of long's iterations (host driver)",
          "[convergence][sim][preset]") {
  // circle_circle with the best preset over its file's thesis one: momentum, population control to
  // iteration 200 at most (a fifth of 1000), the rule every 50 over 100 from 200. The long preset's
  // schedule (events to iteration 800, a 400-iteration window) cannot stop before 1000.
  const auto run = [](const char* preset) {
    CaseConfig config = load_case_file(std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle/case.toml",
                                       {{"preset", preset, "test"}, {"simulation.iterations", "1000", "test"}});
    config.quiet = true;
    MeshInputs inputs(config);
    const SpacingStage spacing(config, inputs);
    NodeSet nodes = make_initial(config, inputs, spacing).nodes;
    SimOptions options = simulation_options(config);
    options.background = &spacing.background();
    return std::pair{options, run_simulation(nodes, *inputs.tree, spacing.field(), options)};
  };
  const auto [fast_options, fast] = run("best");
  CHECK(fast_options.momentum == 0.9);
  CHECK(fast_options.population.enabled);
  CHECK(fast_options.convergence.enabled);
  REQUIRE(fast.converged);
  const int stop = fast.state.iterations_done;
  INFO("the best preset converged after " << stop);
  CHECK(stop % fast_options.convergence.check_every == 0);
  CHECK(stop >= fast_options.convergence.min_iterations);
  CHECK(stop < 1000);
  const auto [long_options, long_run] = run("long");
  CHECK(long_options.momentum == 0.0);
  CHECK_FALSE(long_run.converged);
  CHECK(long_run.state.iterations_done == 1000);
}

namespace {

// A square of side 1 with `side` boundary nodes a side and an interior lattice of spacing 1/side, in the
// metric I * side^2 (a unit mesh): about 2 side^2 triangles with Q near 1.
constexpr int kLatticeSide = 60;
NodeSet unit_lattice() {
  const double h = 1.0 / kLatticeSide;
  NodeSet nodes;
  for (int k = 0; k < 4 * kLatticeSide; ++k) {
    const double t = static_cast<double>(k % kLatticeSide) / kLatticeSide;
    const int edge = k / kLatticeSide;
    const Vec2 p = edge == 0 ? Vec2{t, 0} : edge == 1 ? Vec2{1, t} : edge == 2 ? Vec2{1 - t, 1} : Vec2{0, 1 - t};
    nodes.add(p, h, NodeKind::Boundary, 0);
  }
  std::vector<int> chain(4 * kLatticeSide);
  for (int k = 0; k < 4 * kLatticeSide; ++k) chain[static_cast<std::size_t>(k)] = k;
  chain.push_back(0);
  nodes.curve_nodes = {chain};
  for (int j = 1; j < kLatticeSide; ++j)
    for (int i = 1; i < kLatticeSide; ++i) nodes.add({(i + 0.5 * (j % 2)) * h, j * h}, h, NodeKind::Interior, -1);
  return nodes;
}

ConstantMetricField unit_lattice_metric() {
  const double m = static_cast<double>(kLatticeSide) * kLatticeSide;
  return ConstantMetricField(Metric{m, 0.0, m});
}

// The interior node of lattice row j, column i (1-based, as unit_lattice adds them).
std::size_t lattice_node(int i, int j) {
  return static_cast<std::size_t>(4 * kLatticeSide + (j - 1) * (kLatticeSide - 1) + (i - 1));
}

// The lattice with `count` interior nodes, spread over it, each moved `fraction` of the spacing towards
// its right-hand neighbour (fraction near 1: slivers).
NodeSet lattice_with_moved_nodes(int count, double fraction) {
  NodeSet nodes = unit_lattice();
  const double h = 1.0 / kLatticeSide;
  for (int k = 0; k < count; ++k) {
    const std::size_t n = lattice_node(5 + 7 * (k % 7), 5 + 7 * (k / 7));
    nodes.x[n].x += fraction * h;
    nodes.x[n].y += 0.02 * h;
  }
  return nodes;
}

// The best preset's rule for a metric run (presets.cpp: measured every 50 iterations over a window of
// 100 from 150, tolerances 7e-4 and 3).
ConvergenceOptions metric_best_options() {
  ConvergenceOptions o;
  o.enabled = true;
  o.check_every = 50;
  o.window = 100;
  o.min_iterations = 150;
  o.aspect_tolerance = 7e-4;
  o.angle_tolerance = 3.0;
  return o;
}

}  // namespace

TEST_CASE("metric_worst_count: 1 % of the triangles, rounded up, at least one", "[convergence][metric]") {
  CHECK(metric_worst_count(0) == 0);
  CHECK(metric_worst_count(1) == 1);
  CHECK(metric_worst_count(100) == 1);
  CHECK(metric_worst_count(101) == 2);
  CHECK(metric_worst_count(7000) == 70);
}

TEST_CASE("measure_mesh_in_metric: 60 x the worst 1 %'s mean Q and the others' mean of 1 / Q",
          "[convergence][metric]") {
  const ConstantMetricField field = unit_lattice_metric();
  const NodeSet nodes = lattice_with_moved_nodes(3, 0.97);
  const MeshSample sample = measure_mesh_in_metric(nodes, 100, field);
  // The sample against the mesh's own Q.
  const std::vector<Metric> metrics(nodes.size(), field.at({0, 0}));
  const Mesh mesh = triangulate_in_metric(nodes, {"c0"}, metrics);
  std::vector<double> q = metric_qualities(mesh.points, mesh.triangles, metrics);
  REQUIRE(q.size() > 6000);
  std::sort(q.begin(), q.end());
  const std::size_t worst = (q.size() + 99) / 100;
  double worst_sum = 0.0, inverse = 0.0;
  for (std::size_t i = 0; i < q.size(); ++i) (i < worst ? worst_sum : inverse) += i < worst ? q[i] : 1.0 / q[i];
  CHECK(sample.iteration == 100);
  CHECK(sample.min_angle == Approx(60.0 * worst_sum / static_cast<double>(worst)).epsilon(1e-12));
  CHECK(sample.aspect_ratio == Approx(inverse / static_cast<double>(q.size() - worst)).epsilon(1e-12));
  // Not Q_min's: the slivers are among the worst, but do not make the measure.
  CHECK(q.front() < 0.1);
  CHECK(sample.min_angle > 60.0 * 0.5);
}

TEST_CASE("measure_mesh_in_metric: a few slivers move neither measure by the best preset's tolerances",
          "[convergence][metric]") {
  // One node moved most of the way to a neighbour: slivers with Q below 0.1 among about 7,000 unit
  // triangles. A mean of 1 / Q over all triangles moves by several times the tolerance and Q_min drops
  // to below a tenth; the bulk and the worst 1 % move by less than the tolerances.
  const ConstantMetricField field = unit_lattice_metric();
  const MeshSample lattice = measure_mesh_in_metric(unit_lattice(), 100, field);
  const MeshSample slivers = measure_mesh_in_metric(lattice_with_moved_nodes(1, 0.97), 150, field);
  const ConvergenceOptions o = metric_best_options();
  CHECK(std::abs(slivers.aspect_ratio - lattice.aspect_ratio) < o.aspect_tolerance);
  CHECK(std::abs(slivers.min_angle - lattice.min_angle) < o.angle_tolerance);
}

TEST_CASE("convergence of a metric run: slivers that keep flipping do not hold it, worst triangles that improve do",
          "[convergence][metric]") {
  const ConstantMetricField field = unit_lattice_metric();
  const ConvergenceOptions o = metric_best_options();
  SECTION("slivers that come and go at every measurement: converged one window after the earliest stop") {
    ConvergenceMonitor monitor(o);
    int stopped = 0;
    for (int it = 50; it <= 400 && stopped == 0; it += 50) {
      const NodeSet nodes = (it / 50) % 2 == 0 ? lattice_with_moved_nodes(1, 0.97) : unit_lattice();
      const MeshSample sample = measure_mesh_in_metric(nodes, it, field);
      HistoryRow row;
      row.iteration = it;
      if (monitor.observe(row, &sample)) stopped = it;
    }
    CHECK(stopped == 150);
  }
  SECTION("displaced nodes that move back a little at every measurement: the worst 1 % still improves") {
    // Eight displaced nodes make the worst triangles; their mean Q rises by more than the tolerance
    // from one window to the next, while the bulk moves by less than its tolerance.
    ConvergenceMonitor monitor(o);
    bool stopped = false;
    for (int it = 50; it <= 250 && !stopped; it += 50) {
      const NodeSet nodes = lattice_with_moved_nodes(8, 0.97 - 0.08 * (it / 50 - 1));
      const MeshSample sample = measure_mesh_in_metric(nodes, it, field);
      HistoryRow row;
      row.iteration = it;
      stopped = monitor.observe(row, &sample);
    }
    CHECK_FALSE(stopped);
    CHECK_THAT(monitor.not_converged_reason(250), Catch::Matchers::Contains("smallest angle reached a new best"));
  }
}
