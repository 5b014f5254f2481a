// Population control in a metric (plan_metric_population_event through run_population_event): on a
// hexagonal lattice of unit metric spacing in a constant anisotropic metric (a rhombus of the lattice
// mapped by x -> A x, M = A^-T A^-1), the perfect lattice is left alone, a missing node comes back near
// the hole, an extra node goes, and a boundary gap of metric length 2 gets a node; the isotropic
// planner on the same nodes does otherwise. A hole of the metric at a boundary node (sizes far larger
// there) does not make the gaps beside it short: they are measured along the curve too.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "lattice_rhombus.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/population.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

namespace {

const double kH = std::sqrt(3.0) / 2.0;
// A: sizes 0.2 along 30 degrees, 0.01 across it.
const double kAngle = std::acos(-1.0) / 6.0;
const double kLong = 0.2, kShort = 0.01;

Vec2 map(Vec2 u) {
  const double c = std::cos(kAngle), s = std::sin(kAngle);
  const double a = kLong * u.x, b = kShort * u.y;
  return {c * a - s * b, s * a + c * b};
}
Vec2 lattice(double i, double j) { return map({i + 0.5 * j, kH * j}); }

class ConstantSpacing final : public SpacingField {
 public:
  double at(Vec2) const override { return kShort; }
};

// The mapped rhombus of m x m lattice cells, its curves with a point at every lattice node (every
// `boundary_step` of them), and the metric in which the lattice has unit spacing.
struct MappedRhombus {
  int m;
  Geometry geometry;
  std::unique_ptr<GeometryTree> tree;
  ConstantSpacing spacing;
  ConstantMetricField metric{metric_from_sizes(kLong, kShort, kAngle)};
  NodeSet nodes;

  MappedRhombus(int m_, int boundary_step = 1) : m(m_) {
    geometry = pdmesh_test::lattice_rhombus(m, lattice, boundary_step);
    tree = std::make_unique<GeometryTree>(geometry);
    nodes = make_boundary_nodes(geometry, spacing);
  }

  void fill(int skip_i = -1, int skip_j = -1) {
    for (int j = 1; j < m; ++j)
      for (int i = 1; i < m; ++i)
        if (i != skip_i || j != skip_j) nodes.add(lattice(i, j), kShort, NodeKind::Interior, -1);
  }

  // One event in `field` (the constant metric when null), or isotropic when !in_metric.
  PopulationCounts event(bool in_metric, const MetricField* field = nullptr) {
    PopulationOptions o;
    o.enabled = true;
    BoundaryHandler boundary(*tree, nodes);
    return run_population_event(nodes, boundary, spacing, population_thresholds(o, o.start, 2000), nullptr,
                                in_metric ? (field ? field : &metric) : nullptr);
  }
};

// The rhombus' metric with a hole at `centre`: the metric times s² with s = 1 - (1 - floor) e^(-|p - c|²/w²),
// sizes up to 1/floor times larger within about w of c (as a Hessian's metric is where the function's
// curvature vanishes).
class HoleMetric final : public MetricField {
 public:
  HoleMetric(const Metric& base, Vec2 centre, double floor, double width)
      : base_(base), c_(centre), floor_(floor), w_(width) {}
  Metric at(Vec2 p) const override {
    const double s = 1.0 - (1.0 - floor_) * std::exp(-norm2(p - c_) / (w_ * w_));
    return (s * s) * base_;
  }

 private:
  Metric base_;
  Vec2 c_;
  double floor_, w_;
};

}  // namespace

TEST_CASE("metric population control leaves a unit lattice in the metric alone", "[population][metric]") {
  MappedRhombus r(8);
  r.fill();
  const std::size_t before = r.nodes.size();
  const PopulationCounts c = r.event(true);
  CHECK_FALSE(c.changed());
  CHECK(r.nodes.size() == before);
}

TEST_CASE("metric population control fills a hole of the lattice in the metric", "[population][metric]") {
  MappedRhombus r(8);
  r.fill(4, 4);
  const std::size_t before = r.nodes.size();
  const PopulationCounts c = r.event(true);
  CHECK(c.inserted_interior == 1);
  CHECK(c.removed() == 0);
  REQUIRE(r.nodes.size() == before + 1);
  // The new node (appended) lies near the hole, measured in the metric.
  const Metric m = r.metric.at({0, 0});
  CHECK(m.length(r.nodes.x.back() - lattice(4, 4)) < 0.35);
}

TEST_CASE("metric population control merges two nodes too close in the metric", "[population][metric]") {
  MappedRhombus r(8);
  r.fill();
  // An extra node a fifth of a metric unit from lattice node (3, 5).
  r.nodes.add(lattice(3, 5) + map({0.2, 0.0}), kShort, NodeKind::Interior, -1);
  const std::size_t before = r.nodes.size();
  const PopulationCounts c = r.event(true);
  CHECK(c.merged == 1);
  CHECK(c.inserted() == 0);
  CHECK(r.nodes.size() == before - 1);
}

TEST_CASE("metric population control splits a boundary gap of metric length 2", "[population][metric]") {
  // The curves' points every second lattice node: the boundary nodes are 2 apart in the metric.
  MappedRhombus r(8, 2);
  r.fill();
  const PopulationCounts c = r.event(true);
  CHECK(c.inserted_boundary > 0);
}

TEST_CASE("metric population control keeps the boundary nodes beside a hole of the metric at one of them",
          "[population][metric]") {
  // A hole of the metric (sizes 200 times larger, within 0.01 of it) at boundary node (4, 0): the chords
  // to it measured by their end metrics are about 0.19 long, under merge; the curve between the nodes
  // is about 0.96 long in the metric, so no gap beside the hole is short.
  MappedRhombus r(8);
  r.fill();
  const HoleMetric hole(r.metric.at({0, 0}), lattice(4, 0), 0.005, 0.01);
  const Vec2 a = lattice(3, 0), b = lattice(4, 0);
  REQUIRE(edge_length(hole.at(a), hole.at(b), b - a) < 0.3);
  const PopulationCounts c = r.event(true, &hole);
  CHECK(c.removed_boundary == 0);
  CHECK(c.inserted_boundary == 0);
}

TEST_CASE("the isotropic planner on the stretched lattice is not the metric one", "[population][metric]") {
  // With q = the short size, the lattice's long edges (20 q) look like vacancies to the isotropic
  // rules: the metric is what keeps the lattice as it is.
  MappedRhombus r(8);
  r.fill();
  const PopulationCounts c = r.event(false);
  CHECK(c.changed());
}
