// Tests of the initial nodes of a metric run (init/metric_fill): boundary stations at unit metric
// length (CurveMetricSpacing with spacing_stations) and the interior fill's count and spacing in a
// constant anisotropic metric.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "geometry_fixtures.hpp"
#include "init/boundary_placement.hpp"
#include "init/metric_fill.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"

using namespace pdmesh;

namespace {

class ConstantSpacing final : public SpacingField {
 public:
  explicit ConstantSpacing(double q) : q_(q) {}
  double at(Vec2) const override { return q_; }

 private:
  double q_;
};

// The boundary nodes of the unit square at unit metric length, then the fill.
NodeSet filled_square(const GeometryTree& tree, const MetricField& metric, std::size_t& boundary) {
  const CurveMetricSpacing along(tree, metric);
  const ConstantSpacing q(1.0);
  NodeSet nodes = assemble_boundary_nodes(tree.geometry(), q, spacing_stations(tree.geometry(), along));
  boundary = nodes.size();
  metric_fill(tree, metric, q, nodes);
  return nodes;
}

// The metric length of each node's nearest other node (brute force), interior nodes only.
std::vector<double> nearest_metric_lengths(const NodeSet& nodes, const Metric& m) {
  std::vector<double> out;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] != NodeKind::Interior) continue;
    double best = INFINITY;
    for (std::size_t j = 0; j < nodes.size(); ++j)
      if (j != i) best = std::min(best, m.length(nodes.x[j] - nodes.x[i]));
    out.push_back(best);
  }
  return out;
}

}  // namespace

TEST_CASE("CurveMetricSpacing is the length of a unit metric step along the curve") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  // h = 0.1 along x, 0.01 along y.
  const ConstantMetricField metric(metric_from_sizes(0.1, 0.01, 0.0));
  const CurveMetricSpacing along(tree, metric);
  CHECK(along.at({0.5, 0.0}) == Approx(0.1));    // bottom side: along x
  CHECK(along.at({0.0, 0.37}) == Approx(0.01));  // left side: along y
  // Placed at unit metric length: 10 edges on each horizontal side, 100 on each vertical one.
  const CurveStations stations = spacing_stations(g, along);
  REQUIRE(stations.size() == 4);
  CHECK(stations[0].size() == 11);
  CHECK(stations[1].size() == 101);
  CHECK(stations[2].size() == 11);
  CHECK(stations[3].size() == 101);
}

TEST_CASE("metric_fill reaches the unit mesh's node count in a constant anisotropic metric") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  // Sizes 0.05 and 0.01, the long axis at 30 degrees: C = integral of sqrt(det M) = 1 / (0.05 * 0.01).
  for (const double angle : {0.0, std::numbers::pi / 6}) {
    const ConstantMetricField metric(metric_from_sizes(0.05, 0.01, angle));
    std::size_t boundary = 0;
    const NodeSet nodes = filled_square(tree, metric, boundary);
    const double c = 1.0 / (0.05 * 0.01);
    // A unit mesh has about 4C/sqrt(3) triangles, and by Euler's formula (T + B + 2) / 2 vertices.
    const double ideal = (4.0 * c / std::sqrt(3.0) + static_cast<double>(boundary) + 2.0) / 2.0;
    INFO("angle " << angle << ": " << nodes.size() << " nodes, " << boundary << " on the boundary, ideal " << ideal);
    CHECK(static_cast<double>(nodes.size()) > 0.9 * ideal);
    CHECK(static_cast<double>(nodes.size()) < 1.1 * ideal);
    // Every interior node inside, and no two nodes closer than the fill's minimum distance.
    const std::vector<double> nearest = nearest_metric_lengths(nodes, metric.at({0, 0}));
    REQUIRE_FALSE(nearest.empty());
    CHECK(*std::min_element(nearest.begin(), nearest.end()) >= MetricFillOptions{}.min_distance);
    for (std::size_t i = boundary; i < nodes.size(); ++i) CHECK(tree.inside(nodes.x[i]));
  }
}

TEST_CASE("metric_fill places a hexagonal lattice of unit metric spacing, aligned with the metric") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  const Metric m = metric_from_sizes(0.1, 0.02, 0.0);
  const ConstantMetricField metric(m);
  std::size_t boundary = 0;
  const NodeSet nodes = filled_square(tree, metric, boundary);
  // Most interior nodes have their nearest neighbour at metric length 1 (the lattice), and their six
  // nearest at about 1: count the nodes with six neighbours within [0.9, 1.1].
  std::size_t regular = 0, interior = 0;
  for (std::size_t i = boundary; i < nodes.size(); ++i) {
    ++interior;
    int near = 0;
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      if (j == i) continue;
      const double len = m.length(nodes.x[j] - nodes.x[i]);
      if (len > 0.9 && len < 1.1) ++near;
    }
    regular += near == 6;
  }
  INFO(regular << " of " << interior << " interior nodes have six lattice neighbours");
  CHECK(static_cast<double>(regular) > 0.6 * static_cast<double>(interior));
}
