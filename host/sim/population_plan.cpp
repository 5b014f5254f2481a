// Population-control planning with lengths as ratios to the spacing q: the Delaunay graph of the
// nodes, then the four rules of sim/population_rules.hpp (boundary gaps, clusters, low-valence
// nodes, vacancies), each node in at most one operation.
#include "sim/population_plan.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "sim/delaunay_graph.hpp"
#include "sim/population_rules.hpp"

namespace pdmesh {

void circumcircle(Vec2 a, Vec2 b, Vec2 c, Vec2& centre, double& radius) {
  // Relative to a, so that the result keeps its precision far from the origin.
  const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
  const double d = 2.0 * (bx * cy - by * cx);
  if (d == 0.0) {
    centre = a;
    radius = 0.0;
    return;
  }
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
  centre = {a.x + ux, a.y + uy};
  radius = std::sqrt(ux * ux + uy * uy);
}

namespace {

using population_detail::DelaunayGraph;
using population_detail::Vacancy;

// Lengths as ratios to the spacing q: sigma between two nodes is the mean of their q, at a point it
// is q there. The graph is the nodes' Delaunay graph.
class SpacingRuler {
 public:
  struct At {
    double unit;  // q at the point
  };

  SpacingRuler(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs, const GeometryTree& tree,
               const SpacingField& spacing, std::optional<Triangulation>* kept)
      : graph(graph_of(nodes.x, kept)), nodes_(nodes), arcs_(arcs), tree_(tree), spacing_(spacing) {}

  double gap_ratio(std::size_t c, std::size_t i, std::size_t j) const {
    const std::vector<int>& list = nodes_.curve_nodes[c];
    return (arcs_[c][j] - arcs_[c][i]) / (0.5 * (q(list[i]) + q(list[j])));
  }
  double edge_ratio(int a, int b) const { return dist(x(a), x(b)) / (0.5 * (q(a) + q(b))); }
  double edge_length(int a, int b) const { return dist(x(a), x(b)); }

  At at(Vec2 p) const { return {spacing_.at(p)}; }
  std::optional<At> at_inside(Vec2 p) const {
    const double qp = spacing_.at(p);
    if (!(qp > 0.0) || !std::isfinite(qp) || !tree_.inside(p)) return std::nullopt;
    return At{qp};
  }
  static double distance(const At&, Vec2 a, Vec2 b) { return dist(a, b); }
  double boundary_distance(const At&, Vec2 p) const { return tree_.closest(p).distance; }
  int nearest(const At&, Vec2 p, int start) const { return graph.nearest(nodes_.x, p, start); }

  std::vector<Vacancy> large_triangles(double insert) const {
    std::vector<Vacancy> candidates;
    const auto& tris = graph.triangles;
    // The triangles past the cheap filter, then q at all their circumcentres in one batch (at_many:
    // the same values as at(), on every core; in a settled lattice most triangles pass the filter).
    std::vector<std::size_t> passed;
    std::vector<Vec2> centres;
    std::vector<double> radii;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const auto [a, b, c] = tris[t];
      Vec2 centre;
      double radius = 0.0;
      circumcircle(x(a), x(b), x(c), centre, radius);
      // Cheap filter first: q varies little over a circumradius (a graded field by at most ~25%).
      const double q_min = std::min({q(a), q(b), q(c)});
      if (!(radius > 0.75 * insert * q_min)) continue;
      passed.push_back(t);
      centres.push_back(centre);
      radii.push_back(radius);
    }
    std::vector<double> qcs;
    spacing_.at_many(centres, qcs);
    for (std::size_t k = 0; k < passed.size(); ++k) {
      const double qc = qcs[k], radius = radii[k];
      if (!(qc > 0.0) || !(radius > insert * qc)) continue;
      candidates.push_back({radius / qc, passed[k], centres[k]});
    }
    return candidates;
  }

  const DelaunayGraph graph;

 private:
  // The graph of the points' triangulation; with `kept`, the triangulation kept there whole.
  static DelaunayGraph graph_of(const std::vector<Vec2>& points, std::optional<Triangulation>* kept) {
    if (!kept) return DelaunayGraph(points);
    kept->reset();
    kept->emplace(DelaunayGraph::triangulate(points));
    return DelaunayGraph(static_cast<const Triangulation&>(**kept));
  }

  double q(int i) const { return nodes_.q[static_cast<std::size_t>(i)]; }
  Vec2 x(int i) const { return nodes_.x[static_cast<std::size_t>(i)]; }

  const NodeSet& nodes_;
  const std::vector<std::vector<double>>& arcs_;
  const GeometryTree& tree_;
  const SpacingField& spacing_;
};

}  // namespace

PopulationPlan plan_population_event(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs,
                                     const GeometryTree& tree, const SpacingField& spacing,
                                     const PopulationThresholds& thresholds, std::optional<Triangulation>* kept) {
  const SpacingRuler ruler(nodes, arcs, tree, spacing, kept);
  return population_detail::Planner<SpacingRuler>(nodes, arcs, tree, ruler, thresholds).run();
}

}  // namespace pdmesh
