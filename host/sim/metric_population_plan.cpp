// Population-control planning in a metric field (sim/population_plan.hpp, plan_metric_population_event):
// the four rules of sim/population_rules.hpp with every length measured in the metric, sigma = 1 in
// metric units, on the nodes' Delaunay graph in the metric (mesh/metric_delaunay).
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "mesh/delaunay.hpp"
#include "mesh/metric_delaunay.hpp"
#include "sim/delaunay_graph.hpp"
#include "sim/population_plan.hpp"
#include "sim/population_rules.hpp"
#include "spacing/curve_metric_length.hpp"
#include "spacing/metric_field.hpp"

namespace pdmesh {
namespace {

using population_detail::DelaunayGraph;
using population_detail::Vacancy;

// The nodes' triangulation flipped to the metric's Delaunay (metrics[i] at node i).
DelaunayGraph metric_graph(const std::vector<Vec2>& x, const std::vector<Metric>& metrics) {
  Triangulation dt(x);
  make_metric_delaunay(dt, metrics);
  return DelaunayGraph(std::move(dt));
}

// The circumcentre and circumradius of triangle abc in the constant metric m: the circle through the
// points mapped by m's Cholesky factor L (m = LᵀL), mapped back. Radius 0 and centre a when degenerate.
void metric_circumcircle(const Metric& m, Vec2 a, Vec2 b, Vec2 c, Vec2& centre, double& radius) {
  const double l11 = std::sqrt(m.m11), l12 = m.m12 / l11, l22 = std::sqrt(m.m22 - l12 * l12);
  const auto map = [&](Vec2 p) { return Vec2{l11 * p.x + l12 * p.y, l22 * p.y}; };
  Vec2 u;
  circumcircle(map(a - a), map(b - a), map(c - a), u, radius);
  const double y = u.y / l22;
  centre = a + Vec2{(u.x - l12 * y) / l11, y};
}

// Lengths in the metric, sigma = 1: between two nodes the metric length of their edge
// (spacing/metric.hpp, edge_length), at a point the length in the metric there; a boundary gap is the
// longer of its chord's length and the curve's metric length between its nodes
// (spacing/curve_metric_length), so that a stretch the chord's end metrics miss (the metric large at
// one end, small along the curve between) is split, and one is closed only when both are short. The
// graph is the nodes' Delaunay graph flipped in the metric.
class MetricRuler {
 public:
  struct At {
    Metric m;  // the metric at the point
    double unit = 1.0;
  };

  MetricRuler(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs, const GeometryTree& tree,
              const MetricField& metric)
      : m_(metrics(nodes, metric)),
        graph(metric_graph(nodes.x, m_)),
        nodes_(nodes),
        arcs_(arcs),
        tree_(tree),
        metric_(metric) {}

  // The longer of the chord's metric length and the curve's between curve_nodes[c][i] and [j].
  double gap_ratio(std::size_t c, std::size_t i, std::size_t j) const {
    const std::vector<int>& list = nodes_.curve_nodes[c];
    const double chord = length(list[i], list[j]);
    const double along = curve_metric_length(tree_.geometry().curves[c], metric_, arcs_[c][i], arcs_[c][j]);
    return std::max(chord, along);
  }
  double edge_ratio(int a, int b) const { return length(a, b); }
  double edge_length(int a, int b) const { return length(a, b); }

  At at(Vec2 p) const { return {metric_.at(p)}; }
  std::optional<At> at_inside(Vec2 p) const {
    if (!tree_.inside(p)) return std::nullopt;
    return at(p);
  }
  static double distance(const At& at, Vec2 a, Vec2 b) { return at.m.length(a - b); }
  double boundary_distance(const At& at, Vec2 p) const { return at.m.length(tree_.closest(p).point - p); }

  // The node nearest to p in the metric at p, by a greedy walk over the graph from `start`.
  int nearest(const At& at, Vec2 p, int start) const {
    int v = start;
    double best = at.m.quad(x(v) - p);
    for (;;) {
      int next = v;
      for (const int* u = graph.begin(v); u != graph.end(v); ++u) {
        const double d = at.m.quad(x(*u) - p);
        if (d < best) {
          best = d;
          next = *u;
        }
      }
      if (next == v) return v;
      v = next;
    }
  }

  // Circumcircles in the mean metric of each triangle's corners.
  std::vector<Vacancy> large_triangles(double insert) const {
    std::vector<Vacancy> candidates;
    const auto& tris = graph.triangles;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const auto [a, b, c] = tris[t];
      const Metric mean = (1.0 / 3.0) * (m(a) + m(b) + m(c));
      Vec2 centre;
      double radius = 0.0;
      metric_circumcircle(mean, x(a), x(b), x(c), centre, radius);
      if (radius > insert) candidates.push_back({radius, t, centre});
    }
    return candidates;
  }

 private:
  static std::vector<Metric> metrics(const NodeSet& nodes, const MetricField& metric) {
    std::vector<Metric> m(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) m[i] = metric.at(nodes.x[i]);
    return m;
  }
  Vec2 x(int i) const { return nodes_.x[static_cast<std::size_t>(i)]; }
  const Metric& m(int i) const { return m_[static_cast<std::size_t>(i)]; }
  // The metric length of the edge between nodes a and b (UGAWG's, spacing/metric.hpp).
  double length(int a, int b) const { return pdmesh::edge_length(m(a), m(b), x(b) - x(a)); }

  std::vector<Metric> m_;  // per node (declared before graph, which is built from it)

 public:
  const DelaunayGraph graph;

 private:
  const NodeSet& nodes_;
  const std::vector<std::vector<double>>& arcs_;  // per curve, its nodes' arc positions
  const GeometryTree& tree_;
  const MetricField& metric_;
};

}  // namespace

PopulationPlan plan_metric_population_event(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs,
                                            const GeometryTree& tree, const MetricField& metric,
                                            const PopulationThresholds& thresholds) {
  const MetricRuler ruler(nodes, arcs, tree, metric);
  return population_detail::Planner<MetricRuler>(nodes, arcs, tree, ruler, thresholds).run();
}

}  // namespace pdmesh
