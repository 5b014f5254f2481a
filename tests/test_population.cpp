// Population control (host/sim/population.*): on a hexagonal lattice filling a 60-degree rhombus,
// a missing node comes back near the hole's centre, an extra node goes, a perfect lattice is left
// alone, boundary gaps of 2q get a node in the middle and a crowded boundary node leaves; the node
// set and the boundary handler stay consistent; the schedule and its thresholds.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/delaunay.hpp"
#include "lattice_rhombus.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/population.hpp"
#include "sim/population_plan.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

namespace {

const double kH = std::sqrt(3.0) / 2.0;

Vec2 lattice(double i, double j) { return {i + 0.5 * j, kH * j}; }

// The rhombus with corners lattice(0,0), (m,0), (m,m), (0,m): four straight curves with a point
// every q = 1, so that every boundary lattice node is a curve point.
struct Rhombus {
  int m;
  Geometry geometry;
  std::unique_ptr<GeometryTree> tree;
  ExpressionSpacing spacing{"1"};
  NodeSet nodes;

  explicit Rhombus(int m_) : m(m_) {
    geometry = pdmesh_test::lattice_rhombus(m, lattice);
    tree = std::make_unique<GeometryTree>(geometry);
    nodes = make_boundary_nodes(geometry, spacing);
  }

  // Every interior lattice node, jittered by up to `jitter` q (seeded), except `skip` (i, j).
  void fill(double jitter, int skip_i = -1, int skip_j = -1) {
    std::mt19937_64 rng(7);
    const auto u = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5; };
    for (int j = 1; j < m; ++j)
      for (int i = 1; i < m; ++i) {
        const Vec2 p = lattice(i, j) + Vec2{2.0 * jitter * u(), 2.0 * jitter * u()};
        if (i == skip_i && j == skip_j) continue;
        nodes.add(p, 1.0, NodeKind::Interior, -1);
      }
  }
};

// The first event's thresholds of the default options.
PopulationThresholds first_event() {
  PopulationOptions o;
  o.enabled = true;
  return population_thresholds(o, o.start, 2000);
}

// The handler's arcs equal what a fresh handler computes from the edited node set (so curve_nodes
// is in arc order, every list runs from end point to end point), kinds and curves match the lists.
void check_consistent(const NodeSet& nodes, const BoundaryHandler& edited, const GeometryTree& tree) {
  const BoundaryHandler fresh(tree, nodes);
  REQUIRE(fresh.arcs().size() == edited.arcs().size());
  for (std::size_t c = 0; c < fresh.arcs().size(); ++c) {
    REQUIRE(fresh.arcs()[c].size() == edited.arcs()[c].size());
    for (std::size_t k = 0; k < fresh.arcs()[c].size(); ++k) {
      CHECK(edited.arcs()[c][k] == Approx(fresh.arcs()[c][k]).margin(1e-12));
      if (k > 0) CHECK(edited.arcs()[c][k] > edited.arcs()[c][k - 1]);
    }
  }
  std::vector<int> listed(nodes.size(), 0);
  for (std::size_t c = 0; c < nodes.curve_nodes.size(); ++c)
    for (int v : nodes.curve_nodes[c]) {
      ++listed[static_cast<std::size_t>(v)];
      if (nodes.kind[static_cast<std::size_t>(v)] == NodeKind::Boundary)
        CHECK(nodes.curve[static_cast<std::size_t>(v)] == static_cast<int>(c));
    }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] == NodeKind::Interior) CHECK(listed[i] == 0);
    if (nodes.kind[i] == NodeKind::Boundary) CHECK(listed[i] == 1);
    CHECK(nodes.q[i] == 1.0);
  }
  CHECK(edited.tangents().size() == nodes.size());
}

}  // namespace

TEST_CASE("population: a perfect (jittered) lattice is left alone", "[population]") {
  Rhombus r(12);
  r.fill(0.02);
  BoundaryHandler boundary(*r.tree, r.nodes);
  const NodeSet before = r.nodes;
  const PopulationCounts counts = run_population_event(r.nodes, boundary, r.spacing, first_event());
  CHECK_FALSE(counts.skipped);
  CHECK(counts.inserted() == 0);
  CHECK(counts.removed() == 0);
  CHECK(r.nodes.x == before.x);
  // Nor at the tight end of the schedule.
  PopulationOptions o;
  o.enabled = true;
  const PopulationThresholds last = population_thresholds(o, population_last_event(o, 2000), 2000);
  CHECK_FALSE(run_population_event(r.nodes, boundary, r.spacing, last).changed());
}

TEST_CASE("population: a lattice with one missing node gets one node back near the hole's centre", "[population]") {
  Rhombus r(12);
  r.fill(0.02, 6, 6);
  BoundaryHandler boundary(*r.tree, r.nodes);
  const std::size_t n = r.nodes.size();
  std::vector<int> old_of_new;
  const PopulationCounts counts = run_population_event(r.nodes, boundary, r.spacing, first_event(), &old_of_new);
  CHECK(counts.inserted_interior == 1);
  CHECK(counts.inserted() == 1);
  CHECK(counts.removed() == 0);
  REQUIRE(r.nodes.size() == n + 1);
  CHECK(r.nodes.kind.back() == NodeKind::Interior);
  CHECK(dist(r.nodes.x.back(), lattice(6, 6)) < 0.1);
  REQUIRE(old_of_new.size() == n + 1);
  for (std::size_t i = 0; i < n; ++i) CHECK(old_of_new[i] == static_cast<int>(i));
  CHECK(old_of_new.back() == -1);
  check_consistent(r.nodes, boundary, *r.tree);
  // The hole is filled: a second event finds nothing.
  CHECK_FALSE(run_population_event(r.nodes, boundary, r.spacing, first_event()).changed());
}

TEST_CASE("population: a lattice with one extra node loses one", "[population]") {
  Rhombus r(12);
  r.fill(0.02);
  const std::size_t perfect = r.nodes.size();
  // 0.4 q from a lattice node: a cluster (below merge = 0.6 sigma).
  r.nodes.add(lattice(5, 7) + Vec2{0.4 * std::cos(0.5), 0.4 * std::sin(0.5)}, 1.0, NodeKind::Interior, -1);
  BoundaryHandler boundary(*r.tree, r.nodes);
  const PopulationCounts counts = run_population_event(r.nodes, boundary, r.spacing, first_event());
  CHECK(counts.inserted() == 0);
  CHECK(counts.removed() == 1);
  CHECK(counts.merged == 1);
  CHECK(r.nodes.size() == perfect);
  check_consistent(r.nodes, boundary, *r.tree);
}

// At scale (tens of thousands of nodes, the triangles in the triangulation's order): holes and extra
// nodes spread over the whole lattice are each found once.
TEST_CASE("population: holes and extra nodes spread over a large lattice are each handled once", "[population]") {
  Rhombus r(220);  // ~48k interior nodes, ~96k triangles
  std::vector<Vec2> holes, extras;
  std::mt19937_64 rng(11);
  const auto u = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5; };
  for (int j = 1; j < r.m; ++j)
    for (int i = 1; i < r.m; ++i) {
      if (i % 40 == 20 && j % 40 == 20) {
        holes.push_back(lattice(i, j));
        continue;
      }
      const Vec2 p = lattice(i, j) + Vec2{0.04 * u(), 0.04 * u()};
      r.nodes.add(p, 1.0, NodeKind::Interior, -1);
      if (i % 40 == 0 && j % 40 == 0) {
        extras.push_back(p + Vec2{0.4 * std::cos(0.5), 0.4 * std::sin(0.5)});
        r.nodes.add(extras.back(), 1.0, NodeKind::Interior, -1);
      }
    }
  REQUIRE(holes.size() == 25);
  REQUIRE(extras.size() == 25);
  BoundaryHandler boundary(*r.tree, r.nodes);
  const std::size_t n = r.nodes.size();
  const PopulationCounts counts = run_population_event(r.nodes, boundary, r.spacing, first_event());
  CHECK(counts.inserted_interior == holes.size());
  CHECK(counts.inserted() == holes.size());
  CHECK(counts.merged == extras.size());
  CHECK(counts.removed() == extras.size());
  REQUIRE(r.nodes.size() == n);
  // Each hole has a node near its centre again: one of the appended nodes.
  for (const Vec2& hole : holes) {
    std::size_t near = 0;
    for (std::size_t k = n - holes.size(); k < n; ++k) near += dist(r.nodes.x[k], hole) < 0.1 ? 1 : 0;
    CHECK(near == 1);
  }
  // A second event finds nothing.
  CHECK_FALSE(run_population_event(r.nodes, boundary, r.spacing, first_event()).changed());
}

TEST_CASE("population: an extra node inside a lattice triangle (four neighbours) is removed", "[population]") {
  Rhombus r(12);
  r.fill(0.0);
  const std::size_t perfect = r.nodes.size();
  // Near the centroid of a lattice triangle, 0.52-0.63 q from its corners (above merge = 0.5 here).
  // The centroid lies on the circumcircles of the three neighbouring triangles, so off it the node
  // takes a fourth Delaunay neighbour.
  const Vec2 extra = (1.0 / 3.0) * (lattice(5, 5) + lattice(6, 5) + lattice(5, 6)) + Vec2{0.06, 0.02};
  r.nodes.add(extra, 1.0, NodeKind::Interior, -1);
  BoundaryHandler boundary(*r.tree, r.nodes);
  PopulationThresholds t = first_event();
  t.merge = 0.5;
  t.remove_valence = 4;
  const PopulationCounts counts = run_population_event(r.nodes, boundary, r.spacing, t);
  CHECK(counts.valence == 1);
  CHECK(counts.removed() == 1);
  CHECK(counts.inserted() == 0);
  CHECK(r.nodes.size() == perfect);
  // Off: nothing happens.
  r.nodes.add(extra, 1.0, NodeKind::Interior, -1);
  BoundaryHandler again(*r.tree, r.nodes);
  t.remove_valence = 0;
  CHECK_FALSE(run_population_event(r.nodes, again, r.spacing, t).changed());
}

TEST_CASE("population: boundary nodes 2q apart get a node in the middle of each gap", "[population]") {
  Rhombus r(12);
  r.fill(0.02);
  const NodeSet perfect = r.nodes;
  // Every other boundary node of side ab goes: gaps of 2q.
  std::vector<char> remove(r.nodes.size(), 0);
  const std::vector<int> ab = r.nodes.curve_nodes[0];
  for (std::size_t k = 1; k + 1 < ab.size(); k += 2) remove[static_cast<std::size_t>(ab[k])] = 1;
  BoundaryHandler boundary(*r.tree, r.nodes);
  boundary.remove_nodes(r.nodes, remove);
  check_consistent(r.nodes, boundary, *r.tree);
  const std::size_t n = r.nodes.size();
  REQUIRE(r.nodes.curve_nodes[0].size() == 7);

  const PopulationCounts counts = run_population_event(r.nodes, boundary, r.spacing, first_event());
  CHECK(counts.inserted_boundary == 6);
  CHECK(counts.inserted_interior == 0);
  CHECK(counts.removed() == 0);
  REQUIRE(r.nodes.size() == n + 6);
  check_consistent(r.nodes, boundary, *r.tree);
  // Side ab is back to a node every q, at the lattice positions, in order.
  const std::vector<int>& list = r.nodes.curve_nodes[0];
  REQUIRE(list.size() == 13);
  for (std::size_t k = 0; k < list.size(); ++k) {
    const Vec2 p = r.nodes.x[static_cast<std::size_t>(list[k])];
    CHECK(p.x == Approx(static_cast<double>(k)).margin(1e-12));
    CHECK(p.y == Approx(0.0).margin(1e-12));
  }
  CHECK_FALSE(run_population_event(r.nodes, boundary, r.spacing, first_event()).changed());
}

TEST_CASE("population: a boundary node crowding its neighbour leaves, critical points stay", "[population]") {
  Rhombus r(12);
  r.fill(0.02);
  const std::size_t perfect = r.nodes.size();
  BoundaryHandler boundary(*r.tree, r.nodes);
  // Extra boundary nodes 0.3 q from a regular one (gap 3) and 0.3 q from the critical point b (gap 12).
  boundary.add_boundary(r.nodes, 0, 4, 3.3, 1.0);
  boundary.add_boundary(r.nodes, 0, 13, 11.7, 1.0);
  check_consistent(r.nodes, boundary, *r.tree);
  const PopulationCounts counts = run_population_event(r.nodes, boundary, r.spacing, first_event());
  CHECK(counts.removed_boundary == 2);
  CHECK(counts.removed() == 2);
  CHECK(counts.inserted() == 0);
  CHECK(r.nodes.size() == perfect);
  check_consistent(r.nodes, boundary, *r.tree);
  // Both corners of side ab are still its end points, where they were.
  const std::vector<int>& list = r.nodes.curve_nodes[0];
  CHECK(r.nodes.kind[static_cast<std::size_t>(list.front())] == NodeKind::Fixed);
  CHECK(r.nodes.kind[static_cast<std::size_t>(list.back())] == NodeKind::Fixed);
  CHECK(r.nodes.x[static_cast<std::size_t>(list.back())] == lattice(12, 0));
  for (std::size_t k = 1; k < list.size(); ++k)
    CHECK(dist(r.nodes.x[static_cast<std::size_t>(list[k])], r.nodes.x[static_cast<std::size_t>(list[k - 1])]) > 0.65);
}

TEST_CASE("population: removing a critical point is refused", "[population]") {
  Rhombus r(4);
  BoundaryHandler boundary(*r.tree, r.nodes);
  std::vector<char> remove(r.nodes.size(), 0);
  remove[static_cast<std::size_t>(r.nodes.curve_nodes[0].front())] = 1;
  CHECK_THROWS_AS(boundary.remove_nodes(r.nodes, remove), SimulationError);
}

TEST_CASE("population: coincident nodes skip the event without touching the node set", "[population]") {
  Rhombus r(6);
  r.fill(0.0);
  r.nodes.add(lattice(2, 2), 1.0, NodeKind::Interior, -1);
  BoundaryHandler boundary(*r.tree, r.nodes);
  const NodeSet before = r.nodes;
  const PopulationCounts counts = run_population_event(r.nodes, boundary, r.spacing, first_event());
  CHECK(counts.skipped);
  CHECK_FALSE(counts.changed());
  CHECK(r.nodes.x == before.x);
}

TEST_CASE("population: an event asked to keeps its triangulation of the nodes before it", "[population]") {
  Rhombus r(12);
  r.fill(0.02, 6, 6);
  BoundaryHandler boundary(*r.tree, r.nodes);
  const std::vector<Vec2> before = r.nodes.x;
  std::optional<Triangulation> kept;
  const PopulationCounts counts =
      run_population_event(r.nodes, boundary, r.spacing, first_event(), nullptr, nullptr, &kept);
  CHECK(counts.inserted() == 1);
  REQUIRE(kept.has_value());
  // As the constructor makes it, whole (the graph's own triangulation frees what it does not read).
  const Triangulation fresh(before);
  CHECK(kept->input_count == fresh.input_count);
  CHECK(kept->points == fresh.points);
  CHECK(kept->input_index == fresh.input_index);
  CHECK(kept->vertex_of == fresh.vertex_of);
  CHECK(kept->v == fresh.v);
  CHECK(kept->n == fresh.n);
  CHECK(kept->vertex_triangle == fresh.vertex_triangle);
  // The tracker keeps one only when asked, and an event that skips leaves none.
  PopulationOptions options;
  options.enabled = true;
  PopulationTracker tracker;
  CHECK(tracker.after_iteration(options, options.start, 1000, r.nodes, boundary, r.spacing));
  CHECK_FALSE(tracker.triangulation.has_value());
  tracker.keep_triangulation = true;
  CHECK(tracker.after_iteration(options, tracker.schedule.next, 1000, r.nodes, boundary, r.spacing));
  CHECK(tracker.triangulation.has_value());
  r.nodes.add(r.nodes.x[40], 1.0, NodeKind::Interior, -1);
  BoundaryHandler coincident(*r.tree, r.nodes);
  const auto skipped = tracker.after_iteration(options, tracker.schedule.next, 1000, r.nodes, coincident, r.spacing);
  REQUIRE(skipped);
  CHECK(skipped->skipped);
  CHECK_FALSE(tracker.triangulation.has_value());
}

TEST_CASE("population: the schedule, its ramp and the settled status", "[population]") {
  PopulationOptions o;
  PopulationSchedule s;
  CHECK(population_last_event(o, 2000) == 0);  // off
  CHECK_FALSE(population_event_due(o, s, 100, 2000));
  o.enabled = true;
  o.every = 25;
  o.start = 100;
  o.stop = 0.8;
  o.settle = 0.0;  // the schedule without a settle tolerance: events up to the last one
  CHECK(population_last_event(o, 2000) == 1600);
  // Events that change the node set come every 25 iterations; quiet ones double the interval up to
  // 8 x 25; the last event runs whatever the interval.
  const auto events = [&](const std::vector<int>& changing, int iterations) {
    PopulationSchedule sched;
    std::vector<int> at;
    for (int it = 1; it <= iterations; ++it)
      if (population_event_due(o, sched, it, iterations)) {
        at.push_back(it);
        sched.record(o, it, std::find(changing.begin(), changing.end(), it) != changing.end() ? 1 : 0, 1000);
      }
    return at;
  };
  CHECK(events({100, 125, 150}, 2000) ==
        std::vector<int>{100, 125, 150, 175, 225, 325, 525, 725, 925, 1125, 1325, 1525, 1600});
  CHECK(events({100, 125, 200}, 2000) ==
        std::vector<int>{100, 125, 150, 200, 225, 275, 375, 575, 775, 975, 1175, 1375, 1575, 1600});
  CHECK(events({}, 1990) == std::vector<int>{100, 150, 250, 450, 650, 850, 1050, 1250, 1450, 1592});
  // A run too short for the warm-up has no events.
  CHECK(population_last_event(o, 120) == 0);
  CHECK(events({}, 120).empty());
  // Thresholds ramp linearly from the first to the last event.
  o.insert = {0.9, 0.8};
  o.merge = {0.6, 0.7};
  CHECK(population_thresholds(o, 100, 2000).insert == Approx(0.9));
  CHECK(population_thresholds(o, 850, 2000).insert == Approx(0.85));
  CHECK(population_thresholds(o, 1600, 2000).merge == Approx(0.7));
  // Settled: off, after the last event, or the last event changed nothing.
  CHECK_FALSE(population_status(o, s, 50, 2000).settled);
  CHECK(population_status(o, s, 50, 2000).active);
  s.record(o, 400, 3, 1000);
  CHECK_FALSE(population_status(o, s, 400, 2000).settled);
  s.record(o, 425, 0, 1000);
  CHECK(population_status(o, s, 430, 2000).settled);
  CHECK(population_status(o, s, 430, 2000).active);
  s.record(o, 1600, 3, 1000);
  CHECK(population_status(o, s, 1600, 2000).settled);
  CHECK_FALSE(population_status(o, s, 1600, 2000).active);
  o.enabled = false;
  CHECK(population_status(o, PopulationSchedule{}, 50, 2000).settled);
}

TEST_CASE("population: an event changing at most settle x nodes is quiet, settle_events of them end the events",
          "[population]") {
  PopulationOptions o;
  o.enabled = true;
  o.every = 50;
  o.start = 100;
  o.stop = 0.8;
  o.settle = 1e-3;
  o.settle_events = 2;
  // The tolerance counts inserted plus removed nodes against the node count after the event.
  CHECK(population_quiet(o, 0, 100));
  CHECK_FALSE(population_quiet(o, 1, 100));  // small meshes: only an event that changes nothing
  CHECK(population_quiet(o, 14, 14'000));
  CHECK_FALSE(population_quiet(o, 15, 14'000));
  o.settle = 0.0;
  CHECK(population_quiet(o, 0, 14'000));
  CHECK_FALSE(population_quiet(o, 1, 14'000));
  o.settle = 1e-3;
  // Replays a run of 2000 iterations on 10,000 nodes whose event after iteration `it` changes
  // changes(it) nodes; returns the iterations of the events and checks the status on the way.
  const auto run = [&](const auto& changes, std::vector<int>* settled_at = nullptr) {
    PopulationSchedule s;
    std::vector<int> at;
    for (int it = 1; it <= 2000; ++it) {
      if (population_event_due(o, s, it, 2000)) {
        at.push_back(it);
        s.record(o, it, changes(it), 10'000);
      }
      const PopulationStatus st = population_status(o, s, it, 2000);
      if (settled_at && st.settled && settled_at->empty()) settled_at->push_back(it);
      // Never settled while the last event changed more than the tolerance and events are to come.
      if (st.active && s.last_event > 0 && changes(s.last_event) > 10) CHECK_FALSE(st.settled);
    }
    return at;
  };
  // The annealing lattice: 30 nodes at the first events, then 1-13 per event for the whole run (as
  // 30P30N's trace). Two quiet events in a row (150, then 250 after the doubled interval) end it.
  const auto annealing = [](int it) { return it <= 100 ? 30 : 1 + it % 13; };
  std::vector<int> settled_at;
  CHECK(run(annealing, &settled_at) == std::vector<int>{100, 150, 250});
  CHECK(settled_at == std::vector<int>{150});  // the first quiet event: a stopping rule may start its window
  // A larger change between quiet events restarts the count (and the interval).
  const auto relapse = [](int it) { return it <= 100 ? 30 : it == 250 ? 40 : 2; };
  CHECK(run(relapse) == std::vector<int>{100, 150, 250, 300, 400});
  // One quiet event is enough with settle_events = 1; three need intervals of 50, 100, 200.
  o.settle_events = 1;
  CHECK(run(annealing) == std::vector<int>{100, 150});
  o.settle_events = 3;
  CHECK(run(annealing) == std::vector<int>{100, 150, 250, 450});
  // Without a tolerance the same run has events to the last one, and is settled only past it.
  o.settle = 0.0;
  settled_at.clear();
  const std::vector<int> all = run(annealing, &settled_at);
  CHECK(all.back() == 1600);
  CHECK(all.size() == 31);
  CHECK(settled_at == std::vector<int>{1600});
  // A finished schedule: no event, not active, settled (a checkpoint's schedule resumes the same).
  o.settle = 1e-3;
  o.settle_events = 2;
  PopulationSchedule s;
  s.record(o, 100, 30, 10'000);
  CHECK_FALSE(s.finished(o));
  s.record(o, 150, 5, 10'000);
  CHECK_FALSE(s.finished(o));
  CHECK(population_status(o, s, 160, 2000).settled);
  CHECK(population_status(o, s, 160, 2000).active);
  s.record(o, 250, 5, 10'000);
  CHECK(s.finished(o));
  const PopulationSchedule resumed{s.next, s.interval, s.last_event, s.last_change};
  CHECK(resumed.finished(o));
  CHECK_FALSE(population_event_due(o, resumed, resumed.next, 2000));
  CHECK_FALSE(population_event_due(o, resumed, 1600, 2000));
  CHECK_FALSE(population_status(o, resumed, 300, 2000).active);
  CHECK(population_status(o, resumed, 300, 2000).settled);
}
