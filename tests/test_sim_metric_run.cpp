// Whole runs in a metric (SimOptions::metric): run_simulation with a constant M = I / q^2 repeats the
// isotropic run with spacing q bit for bit; a run in UGAWG's linear metric relaxes to nodes at unit
// metric length from their nearest neighbours; its stopping rule measures in the metric; the host
// driver over the OpenCL step backend repeats the reference's metric run bit for bit in double;
// population control measures in the metric; the device-resident simulator refuses a metric.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <vector>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry_fixtures.hpp"
#include "init/initial_distribution.hpp"
#include "opencl/device_simulation.hpp"
#include "opencl/opencl_backend.hpp"
#include "sim/convergence.hpp"
#include "sim/reference/metric_pair.hpp"
#include "sim/simulation.hpp"
#include "sim_fixtures.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"
#include "step_backend_inputs.hpp"

using namespace pdmesh;
using pdmesh_test::uniform;

namespace {

class ConstantSpacing final : public SpacingField {
 public:
  explicit ConstantSpacing(double q) : q_(q) {}
  double at(Vec2) const override { return q_; }

 private:
  double q_;
};

// UGAWG's linear case: h_x = 0.1, h_y = 0.001 + 0.198 |y - 0.5|.
Metric linear_metric(double y) {
  const double hy = 0.001 + 0.198 * std::fabs(y - 0.5);
  return Metric{100.0, 0.0, 1.0 / (hy * hy)};
}

class LinearMetric final : public MetricField {
 public:
  Metric at(Vec2 p) const override { return linear_metric(p.y); }
};

// The linear metric's largest size, as NodeSet::q of a metric run.
class LinearLargestSize final : public SpacingField {
 public:
  double at(Vec2 p) const override {
    const Metric m = linear_metric(p.y);
    return reference::largest_size(m.m11, m.m12, m.m22);
  }
};

// Positions, kinds and the history of two runs agree bit for bit. The history's force sums of run b
// are in units `scale` times run a's (a metric run measures |F| in the metric: |F|_M = |F| / q for
// M = I / q^2, exact for q a power of two), its kinetic sums in scale^2.
void require_same_run(const NodeSet& a, const SimResult& ra, const NodeSet& b, const SimResult& rb,
                      double scale = 1.0) {
  REQUIRE(a.size() == b.size());
  REQUIRE(a.kind == b.kind);
  REQUIRE(a.curve_nodes == b.curve_nodes);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differ += (a.x[i].x != b.x[i].x || a.x[i].y != b.x[i].y);
  REQUIRE(differ == 0);
  REQUIRE(ra.history.size() == rb.history.size());
  for (std::size_t k = 0; k < ra.history.size(); ++k) {
    INFO("history row " << k);
    REQUIRE(ra.history[k].average_force * scale == rb.history[k].average_force);
    REQUIRE(ra.history[k].max_force * scale == rb.history[k].max_force);
    REQUIRE(ra.history[k].average_kinetic * (scale * scale) == rb.history[k].average_kinetic);
    REQUIRE(ra.history[k].dt_gm == rb.history[k].dt_gm);
    REQUIRE(ra.history[k].snapped == rb.history[k].snapped);
  }
}

// The unit square's linear case as a NodeSet: the corners Fixed, the sides' nodes at unit metric
// length (10 pieces along x; ln(100) / 0.198 per half along y in 23 pieces) sliding along their side,
// and as many random interior nodes as a unit mesh holds, with density sqrt(det M).
NodeSet linear_case_nodes() {
  NodeSet nodes;
  nodes.curve_nodes.resize(4);
  const LinearLargestSize size;
  auto put = [&](Vec2 x, NodeKind kind, int curve) {
    const int i = nodes.add(x, size.at(x), kind, curve);
    if (curve >= 0 && kind == NodeKind::Boundary) nodes.curve_nodes[static_cast<std::size_t>(curve)].push_back(i);
    return i;
  };
  // fixtures::square's sides: 0 (0,0)->(1,0), 1 (1,0)->(1,1), 2 (1,1)->(0,1), 3 (0,1)->(0,0).
  const int c00 = put({0, 0}, NodeKind::Fixed, 0), c10 = put({1, 0}, NodeKind::Fixed, 0);
  const int c11 = put({1, 1}, NodeKind::Fixed, 1), c01 = put({0, 1}, NodeKind::Fixed, 2);
  const double half = std::log(100.0) / 0.198;
  auto y_at = [&](int k) {
    return 0.5 + std::copysign((std::exp(0.198 * half * std::abs(k) / 23.0) - 1.0) * 0.001 / 0.198, k);
  };
  nodes.curve_nodes[0].push_back(c00);
  for (int k = 1; k < 10; ++k) put({0.1 * k, 0.0}, NodeKind::Boundary, 0);
  nodes.curve_nodes[0].push_back(c10);
  nodes.curve_nodes[1].push_back(c10);
  for (int k = -22; k <= 22; ++k) put({1.0, y_at(k)}, NodeKind::Boundary, 1);
  nodes.curve_nodes[1].push_back(c11);
  nodes.curve_nodes[2].push_back(c11);
  for (int k = 1; k < 10; ++k) put({1.0 - 0.1 * k, 1.0}, NodeKind::Boundary, 2);
  nodes.curve_nodes[2].push_back(c01);
  nodes.curve_nodes[3].push_back(c01);
  for (int k = 22; k >= -22; --k) put({0.0, y_at(k)}, NodeKind::Boundary, 3);
  nodes.curve_nodes[3].push_back(c00);
  const std::size_t boundary = nodes.size();
  const double complexity = 2.0 * 10.0 * half;  // the integral of sqrt(det M) = 10 / h_y over the square
  const auto interior = static_cast<std::size_t>(2.0 * complexity / std::sqrt(3.0) - boundary / 2.0 + 1.0);
  std::mt19937_64 rng(5);
  while (nodes.size() < boundary + interior) {
    const double x = uniform(rng), y = uniform(rng);
    if (x <= 0.0 || y <= 0.0) continue;
    if (uniform(rng) * 1000.0 <= 1.0 / (0.001 + 0.198 * std::fabs(y - 0.5))) put({x, y}, NodeKind::Interior, -1);
  }
  return nodes;
}

SimOptions linear_options(const MetricField& metric, int iterations) {
  SimOptions o;
  o.iterations = iterations;
  o.dt_initial = 0.03;
  o.momentum = 0.9;
  o.stability_factor = 1.0;
  o.exact_spacing = true;
  o.quiet = true;
  o.metric = &metric;
  return o;
}

}  // namespace

TEST_CASE("run_simulation with a constant metric I / q^2 repeats the isotropic run with spacing q bit for bit",
          "[sim][metric]") {
  // q a power of two: M^(-1/2) = q I and the metric distance |d| / q are exact, so the metric pair
  // force is the isotropic one to the last bit (sim/reference/metric_pair.hpp).
  const double q = 0.0625;
  const Geometry geometry = fixtures::square(1.0, 16);
  const GeometryTree tree(geometry);
  const ConstantSpacing spacing(q);
  const NodeSet initial = make_initial_distribution(tree, spacing, {InitMethod::Random, 3, {}}).nodes;
  const ConstantMetricField metric(Metric{1.0 / (q * q), 0.0, 1.0 / (q * q)});
  for (const double momentum : {0.0, 0.9}) {
    INFO("momentum " << momentum);
    SimOptions o;
    o.iterations = 150;
    o.dt_initial = 0.01;
    o.momentum = momentum;
    o.quiet = true;
    NodeSet iso = initial, met = initial;
    const SimResult a = run_simulation(iso, tree, spacing, o);
    o.metric = &metric;
    const SimResult b = run_simulation(met, tree, spacing, o);
    require_same_run(iso, a, met, b, 1.0 / q);
    // The run moved the nodes (a run that stood still would pass trivially).
    double moved = 0.0;
    for (std::size_t i = 0; i < iso.size(); ++i)
      if (i < initial.size())
        moved = std::max(moved, std::hypot(iso.x[i].x - initial.x[i].x, iso.x[i].y - initial.x[i].y));
    REQUIRE(moved > 0.1 * q);
  }
}

TEST_CASE("run_simulation in the linear metric relaxes the nodes to unit metric length", "[sim][metric]") {
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  const LinearLargestSize spacing;
  const LinearMetric metric;
  NodeSet nodes = linear_case_nodes();
  const SimResult result = run_simulation(nodes, tree, spacing, linear_options(metric, 1500));
  REQUIRE(result.history.size() == 1500);
  std::vector<double> nearest;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] != NodeKind::Interior) continue;
    REQUIRE(tree.inside(nodes.x[i]));
    double best = HUGE_VAL;
    for (std::size_t j = 0; j < nodes.size(); ++j)
      if (j != i)
        best = std::min(best,
                        edge_length(linear_metric(nodes.x[i].y), linear_metric(nodes.x[j].y), nodes.x[j] - nodes.x[i]));
    nearest.push_back(best);
  }
  std::sort(nearest.begin(), nearest.end());
  INFO("snapped " << result.stats.snapped << "; nearest-neighbour metric lengths: min " << nearest.front()
                  << ", median " << nearest[nearest.size() / 2] << ", max " << nearest.back());
  REQUIRE(nearest.size() > 400);
  REQUIRE(nearest[nearest.size() / 2] == Approx(1.0).margin(0.05));
  REQUIRE(nearest.front() > 0.8);
  REQUIRE(nearest.back() < 1.2);
  // The sides' sliding nodes keep unit metric length along their side.
  for (const auto& side : nodes.curve_nodes)
    for (std::size_t k = 1; k < side.size(); ++k) {
      const Vec2 a = nodes.x[static_cast<std::size_t>(side[k - 1])], b = nodes.x[static_cast<std::size_t>(side[k])];
      REQUIRE(edge_length(linear_metric(a.y), linear_metric(b.y), b - a) == Approx(1.0).margin(0.25));
    }
}

namespace {

// The linear metric's largest size, counting its look-ups.
class CountingSize final : public SpacingField {
 public:
  double at(Vec2 p) const override {
    ++calls;
    return size_.at(p);
  }
  mutable std::atomic<std::size_t> calls{0};

 private:
  LinearLargestSize size_;
};

}  // namespace

TEST_CASE("a metric run looks q up when it hands its nodes back, an isotropic run after every iteration",
          "[sim][metric]") {
  // The metric step never reads q; the node set handed back still has every node's q at its position.
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  const LinearMetric metric;
  const NodeSet start = linear_case_nodes();
  const std::size_t n = start.size();
  for (const bool with_metric : {true, false}) {
    INFO((with_metric ? "metric run" : "isotropic run"));
    const CountingSize spacing;
    NodeSet nodes = start;
    // A few isotropic iterations: q (the metric's largest size) is far too large for the layer's nodes.
    const int iterations = with_metric ? 40 : 4;
    SimOptions o = linear_options(metric, iterations);
    if (!with_metric) o.metric = nullptr;
    const SimResult r = run_simulation(nodes, tree, spacing, o);
    REQUIRE(r.history.size() == static_cast<std::size_t>(iterations));
    REQUIRE(nodes.size() == n);
    if (with_metric)
      CHECK(spacing.calls.load() <= 2 * n);
    else
      CHECK(spacing.calls.load() >= static_cast<std::size_t>(iterations) * n);
    const LinearLargestSize exact;
    std::size_t stale = 0;
    for (std::size_t i = 0; i < n; ++i) stale += nodes.q[i] != exact.at(nodes.x[i]);
    CHECK(stale == 0);
  }
}

TEST_CASE("the stopping rule of a metric run measures the mesh in the metric and stops the linear run",
          "[sim][metric][convergence]") {
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  const LinearLargestSize spacing;
  const LinearMetric metric;
  NodeSet nodes = linear_case_nodes();
  SimOptions o = linear_options(metric, 3000);
  o.convergence.enabled = true;
  const SimResult r = run_simulation(nodes, tree, spacing, o);
  // The measurements are the metric mesh's: mean 1/Q near 1 and 60 Q_min of a unit mesh. The
  // isotropic ones (aspect ratio R/2r of triangles 100x stretched) are far from both.
  REQUIRE(r.state.convergence.size() >= 4);
  const MeshSample& last = r.state.convergence.back();
  INFO("last measurement at " << last.iteration << ": mean 1/Q " << last.aspect_ratio << ", 60 Q_min "
                              << last.min_angle);
  REQUIRE(last.aspect_ratio < 1.1);
  REQUIRE(last.min_angle > 30.0);
  const MeshSample iso = measure_mesh(nodes, last.iteration);
  REQUIRE(iso.aspect_ratio > 5.0);
  // It stops: the mesh in the metric settles long before the maximum.
  REQUIRE(r.converged);
  REQUIRE(r.history.size() < 3000);
}

TEST_CASE("population control in a metric run measures in the metric", "[sim][metric][population]") {
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  // NodeSet::q is the metric's largest size (0.1 at the layer, where the nodes are 0.001 apart across
  // it): population control by q would merge most of the layer's nodes.
  const LinearLargestSize spacing;
  const LinearMetric metric;
  NodeSet nodes = linear_case_nodes();
  const std::size_t before = nodes.size();
  SimOptions o = linear_options(metric, 400);
  o.population.enabled = true;
  const SimResult r = run_simulation(nodes, tree, spacing, o);
  REQUIRE(r.stats.population_events > 0);
  // The random start has clusters and vacancies: the events change nodes, and keep the count near
  // the unit mesh's.
  REQUIRE(r.stats.inserted + r.stats.removed > 0);
  INFO(before << " nodes before, " << nodes.size() << " after");
  REQUIRE(static_cast<double>(nodes.size()) > 0.9 * static_cast<double>(before));
  REQUIRE(static_cast<double>(nodes.size()) < 1.15 * static_cast<double>(before));
}

TEST_CASE("the host driver over the OpenCL step backend repeats the reference's metric run in double",
          "[sim][metric][opencl]") {
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  const LinearLargestSize spacing;
  const LinearMetric metric;
  const NodeSet initial = linear_case_nodes();
  NodeSet host = initial, device = initial;
  const SimOptions o = linear_options(metric, 40);
  const SimResult a = make_host_simulator()->run(host, tree, spacing, o);
  const auto simulator = make_host_simulator(
      ocl::make_opencl_backend(pdmesh::test::test_context(), ocl::Precision::Double), "opencl step backend");
  REQUIRE(simulator->describe() == "opencl step backend");
  const SimResult b = simulator->run(device, tree, spacing, o);
  require_same_run(host, a, device, b);
}

TEST_CASE("the device-resident simulator refuses a metric run with an InputError naming why", "[sim][metric][opencl]") {
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  const LinearLargestSize spacing;
  const LinearMetric metric;
  NodeSet nodes = linear_case_nodes();
  const NodeSet before = nodes;
  SimOptions o = linear_options(metric, 10);
  o.exact_spacing = false;
  ocl::DeviceSimulator simulator(pdmesh::test::test_context(), ocl::Precision::Double);
  REQUIRE_THROWS_WITH(simulator.run(nodes, tree, spacing, o),
                      Catch::Contains("no metric mode") && Catch::Contains("host driver"));
  REQUIRE_THROWS_AS(simulator.run(nodes, tree, spacing, o), InputError);
  REQUIRE(nodes.x == before.x);
  // Without the metric the same run goes ahead.
  o.metric = nullptr;
  REQUIRE(simulator.run(nodes, tree, spacing, o).history.size() == 10);
}

TEST_CASE("a metric run under the stopping rule anneals dt_GM from population control's last event",
          "[sim][metric][convergence]") {
  const LinearMetric metric;
  SimOptions o;
  o.iterations = 2000;
  REQUIRE(metric_anneal_from(o) == 0);  // isotropic
  o.metric = &metric;
  REQUIRE(metric_anneal_from(o) == 0);  // no stopping rule
  o.convergence.enabled = true;
  o.convergence.min_iterations = 150;
  o.convergence.window = 100;
  o.convergence.check_every = 50;
  REQUIRE(metric_anneal_from(o) == 250);  // no population control: the earliest stop plus one window
  o.population.enabled = true;
  o.population.stop = 0.2;
  REQUIRE(metric_anneal_from(o) == 400);
  o.population.stop = 0.15;  // the best preset's
  REQUIRE(metric_anneal_from(o) == 300);
  o.iterations = 500;
  REQUIRE(metric_anneal_from(o) == 250);
  o.metric_anneal = 1.0;
  REQUIRE(metric_anneal_from(o) == 0);
}

namespace {

// linear_options under the stopping rule (a measurement every 50 iterations, a window of 100, the
// earliest stop at 150) with the given bulk tolerance.
SimOptions stopping_linear_options(const MetricField& metric, int iterations, double aspect_tolerance) {
  SimOptions o = linear_options(metric, iterations);
  o.convergence.enabled = true;
  o.convergence.aspect_tolerance = aspect_tolerance;
  o.convergence.check_every = 50;
  o.convergence.window = 100;
  o.convergence.min_iterations = 150;
  return o;
}

}  // namespace

TEST_CASE("annealing settles a metric run the dt_GM rule keeps moving, and only after its start",
          "[sim][metric][convergence]") {
  // The linear case from a random start under a bulk tolerance of 2e-5: at the rule's step its nodes
  // still move the mesh's mean 1/Q by more than that over every window up to the maximum.
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  const LinearLargestSize spacing;
  const LinearMetric metric;
  SimOptions o = stopping_linear_options(metric, 1500, 2e-5);
  const int from = metric_anneal_from(o);
  REQUIRE(from == 250);
  NodeSet annealed = linear_case_nodes(), plain = annealed;
  const SimResult a = run_simulation(annealed, tree, spacing, o);
  o.metric_anneal = 1.0;
  const SimResult b = run_simulation(plain, tree, spacing, o);
  // The same run up to the start.
  REQUIRE(a.history.size() > static_cast<std::size_t>(from));
  for (std::size_t k = 0; k < static_cast<std::size_t>(from); ++k) REQUIRE(a.history[k].dt_gm == b.history[k].dt_gm);
  // After it each step is the rule's (x 1, 1.01 or 0.99) times the factor.
  const double factor = SimOptions{}.metric_anneal;
  for (std::size_t k = static_cast<std::size_t>(from); k < a.history.size(); ++k) {
    INFO("iteration " << a.history[k].iteration);
    const double ratio = a.history[k].dt_gm / a.history[k - 1].dt_gm / factor;
    const bool rule = ratio == Approx(1.0).epsilon(1e-12) || ratio == Approx(1.01).epsilon(1e-12) ||
                      ratio == Approx(0.99).epsilon(1e-12);
    REQUIRE(rule);
  }
  INFO("annealed: " << a.history.size() << " iterations; plain: " << b.history.size());
  REQUIRE(a.converged);
  REQUIRE(!b.converged);
  REQUIRE(b.history.size() == 1500);
}

TEST_CASE("a metric run stopped while annealing and resumed ends as the uninterrupted run",
          "[sim][metric][convergence]") {
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  const LinearLargestSize spacing;
  const LinearMetric metric;
  SimOptions o = stopping_linear_options(metric, 400, 0.0);  // never converged: both runs go to 400
  REQUIRE(metric_anneal_from(o) == 250);
  const NodeSet start = linear_case_nodes();
  NodeSet whole = start, parts = start;
  const SimResult a = run_simulation(whole, tree, spacing, o);
  SimCallbacks callbacks;
  callbacks.on_iteration = [](const HistoryRow& row) {
    if (row.iteration == 300) interrupt_flag().store(true);
  };
  const SimResult b = run_simulation(parts, tree, spacing, o, callbacks);
  interrupt_flag().store(false);
  REQUIRE(b.stopped);
  REQUIRE(b.state.iterations_done == 300);
  SimOptions again = o;
  again.resume = &b.state;
  const SimResult c = run_simulation(parts, tree, spacing, again);
  REQUIRE(c.state.iterations_done == 400);
  REQUIRE(c.state.time_step.dt == a.state.time_step.dt);
  // Annealed over iterations 251-400: at most 0.99^150 x 1.01^30 = 0.30 x what it was (the rule alone:
  // at least 0.99^30 = 0.74).
  REQUIRE(a.history[399].dt_gm < 0.4 * a.history[249].dt_gm);
  REQUIRE(parts.size() == whole.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < whole.size(); ++i)
    differ += (parts.x[i].x != whole.x[i].x || parts.x[i].y != whole.x[i].y);
  REQUIRE(differ == 0);
}
