// The four population-control rules (boundary gaps, clusters, low-valence nodes, vacancies), written
// once for the isotropic planner (sim/population_plan.cpp) and the metric one
// (sim/metric_population_plan.cpp). What differs between them is a Ruler:
//   graph                          the nodes' Delaunay graph (Euclidean, or flipped in the metric)
//   gap_ratio(c, i, j)             the boundary stretch between curve_nodes[c][i] and [j] over sigma
//   edge_ratio(a, b)               the edge between nodes a and b over sigma
//   edge_length(a, b)              the edge's length (compared only with the triangle's other edges)
//   at(p) -> At                    the measure at point p; At::unit is sigma there
//   at_inside(p) -> optional<At>   the same, empty when p is outside the domain or has no valid size
//   distance(at, a, b)             the distance between a and b measured at p
//   boundary_distance(at, p)       p's distance from the closest boundary point, measured at p
//   nearest(at, p, start)          the node nearest to p, by a walk over the graph from start
//   large_triangles(insert)        every triangle whose circumradius over sigma exceeds insert, in
//                                  triangle order: {ratio, triangle index, circumcentre}
// Thresholds compare a length with factor * unit (unit 1 in the metric). Every loop runs in node,
// edge or sorted order with index tie-breaks, so a plan is reproducible.
#pragma once
#include <algorithm>
#include <cstddef>
#include <optional>
#include <tuple>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "nodes/node_set.hpp"
#include "sim/delaunay_graph.hpp"
#include "sim/population_plan.hpp"
#include "sim/population_profile.hpp"

namespace pdmesh::population_detail {

// A triangle whose circumcircle leaves room for a node.
struct Vacancy {
  double ratio;   // circumradius over sigma
  std::size_t t;  // index into graph.triangles
  Vec2 centre;    // circumcentre
};

template <class Ruler>
class Planner {
 public:
  Planner(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs, const GeometryTree& tree,
          const Ruler& ruler, const PopulationThresholds& t)
      : nodes_(nodes), arcs_(arcs), tree_(tree), ruler_(ruler), t_(t), graph_(ruler.graph), used_(nodes.size(), 0) {
    plan_.remove.assign(nodes.size(), 0);
  }

  PopulationPlan run() {
    if (t_.boundary) {
      const population_profile::Timer timer("boundary gaps");
      boundary_gaps();
    }
    {
      const population_profile::Timer timer("clusters");
      clusters();
    }
    if (t_.remove_valence > 0) {
      const population_profile::Timer timer("low valence");
      low_valence();
    }
    const population_profile::Timer timer("vacancies");
    vacancies();
    return std::move(plan_);
  }

 private:
  using At = typename Ruler::At;

  bool is(int i, NodeKind k) const { return nodes_.kind[static_cast<std::size_t>(i)] == k; }
  Vec2 x(int i) const { return nodes_.x[static_cast<std::size_t>(i)]; }
  bool used(int i) const { return used_[static_cast<std::size_t>(i)] != 0; }
  void use(int i) { used_[static_cast<std::size_t>(i)] = 1; }
  void use_ring(int i) {
    use(i);
    for (const int* u = graph_.begin(i); u != graph_.end(i); ++u) use(*u);
  }
  void remove(int i) {
    plan_.remove[static_cast<std::size_t>(i)] = 1;
    use(i);
  }

  // Long gaps get a node at their middle (longest first); short gaps lose a Boundary node (shortest
  // first) when the gap that results stays below the split threshold.
  void boundary_gaps() {
    struct Gap {
      double ratio;
      int curve;
      std::size_t k;
    };
    std::vector<Gap> long_gaps, short_gaps;
    for (std::size_t c = 0; c < nodes_.curve_nodes.size(); ++c) {
      const std::vector<int>& list = nodes_.curve_nodes[c];
      for (std::size_t k = 1; k < list.size(); ++k) {
        const double ratio = ruler_.gap_ratio(c, k - 1, k);
        if (ratio > t_.boundary_split) long_gaps.push_back({ratio, static_cast<int>(c), k});
        if (ratio < t_.merge) short_gaps.push_back({ratio, static_cast<int>(c), k});
      }
    }
    const auto order = [](const Gap& a, const Gap& b) {
      return std::tie(a.ratio, a.curve, a.k) < std::tie(b.ratio, b.curve, b.k);
    };
    std::sort(long_gaps.begin(), long_gaps.end(), [&](const Gap& a, const Gap& b) { return order(b, a); });
    std::sort(short_gaps.begin(), short_gaps.end(), order);
    for (const Gap& g : long_gaps) split_gap(g.curve, g.k);
    for (const Gap& g : short_gaps) close_gap(g.curve, g.k);
  }

  void split_gap(int curve, std::size_t k) {
    const auto c = static_cast<std::size_t>(curve);
    const std::vector<int>& list = nodes_.curve_nodes[c];
    const int a = list[k - 1], b = list[k];
    // Splits of neighbouring gaps share an end node without conflict; anything else blocks.
    if (used_[static_cast<std::size_t>(a)] == 1 || used_[static_cast<std::size_t>(b)] == 1) return;
    const double arc = 0.5 * (arcs_[c][k - 1] + arcs_[c][k]);
    if (!(arcs_[c][k - 1] < arc && arc < arcs_[c][k])) return;
    const Curve& geometry_curve = tree_.geometry().curves[c];
    if (geometry_curve.fixed_points) return;  // a layer front: its nodes are the layer cells'
    // The point on the curve (the same search BoundaryHandler::add_boundary makes).
    const Vec2 p = point_at_arc(geometry_curve, arc);
    const At at = ruler_.at(p);
    // No other node (an interior node bulging into the gap) may be closer than a cluster.
    for (int end : {a, b})
      for (const int* u = graph_.begin(end); u != graph_.end(end); ++u)
        if (*u != a && *u != b && ruler_.distance(at, x(*u), p) < t_.merge * at.unit) return;
    plan_.boundary_inserts.push_back({curve, k, arc});
    ++plan_.counts.inserted_boundary;
    used_[static_cast<std::size_t>(a)] = std::max<char>(used_[static_cast<std::size_t>(a)], 2);
    used_[static_cast<std::size_t>(b)] = std::max<char>(used_[static_cast<std::size_t>(b)], 2);
  }

  void close_gap(int curve, std::size_t k) {
    const auto c = static_cast<std::size_t>(curve);
    const std::vector<int>& list = nodes_.curve_nodes[c];
    // Candidates: list[k - 1] (merged gap from list[k - 2] to list[k]) and list[k] (list[k - 1] to list[k + 1]).
    int best = -1;
    double best_ratio = t_.boundary_split;
    for (std::size_t m : {k - 1, k}) {
      if (m == 0 || m + 1 >= list.size() || !is(list[m], NodeKind::Boundary)) continue;
      const int before = list[m - 1], node = list[m], after = list[m + 1];
      if (used(before) || used(node) || used(after)) continue;
      const double ratio = ruler_.gap_ratio(c, m - 1, m + 1);
      if (ratio < best_ratio) {
        best_ratio = ratio;
        best = static_cast<int>(m);
      }
    }
    if (best < 0) return;
    const auto m = static_cast<std::size_t>(best);
    remove(list[m]);
    use(list[m - 1]);
    use(list[m + 1]);
    ++plan_.counts.removed_boundary;
  }

  // Graph edges shorter than merge * sigma, shortest first: two interior nodes merge into their
  // midpoint; an interior node next to a boundary or fixed node leaves.
  void clusters() {
    struct Edge {
      double ratio;
      int a, b;
    };
    std::vector<Edge> short_edges;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const int a = static_cast<int>(i);
      for (const int* u = graph_.begin(a); u != graph_.end(a); ++u) {
        const int b = *u;
        if (b <= a || (!is(a, NodeKind::Interior) && !is(b, NodeKind::Interior))) continue;
        const double ratio = ruler_.edge_ratio(a, b);
        if (ratio < t_.merge) short_edges.push_back({ratio, a, b});
      }
    }
    std::sort(short_edges.begin(), short_edges.end(),
              [](const Edge& e, const Edge& f) { return std::tie(e.ratio, e.a, e.b) < std::tie(f.ratio, f.a, f.b); });
    for (const Edge& e : short_edges) {
      if (used(e.a) || used(e.b)) continue;
      const bool a_in = is(e.a, NodeKind::Interior), b_in = is(e.b, NodeKind::Interior);
      if (a_in && b_in) {
        // Never across a wall: the pair must see each other inside the domain.
        if (tree_.crosses_boundary(x(e.a), x(e.b))) continue;
        plan_.moves.emplace_back(e.a, 0.5 * (x(e.a) + x(e.b)));
        remove(e.b);
        use(e.a);
        ++plan_.counts.merged;
      } else {
        const int inner = a_in ? e.a : e.b, outer = a_in ? e.b : e.a;
        // crosses_boundary allows its first point on the boundary.
        if (tree_.crosses_boundary(x(outer), x(inner))) continue;
        remove(inner);
        use(outer);
        ++plan_.counts.thinned;
      }
    }
  }

  void low_valence() {
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const int v = static_cast<int>(i);
      if (!is(v, NodeKind::Interior) || graph_.on_hull[i] || used(v)) continue;
      if (graph_.valence(v) > static_cast<std::size_t>(t_.remove_valence)) continue;
      bool free = true;
      for (const int* u = graph_.begin(v); u != graph_.end(v) && free; ++u) free = !used(*u);
      if (!free) continue;
      use_ring(v);
      remove(v);
      ++plan_.counts.valence;
    }
  }

  // Whether p can take a new interior node: inside, clear of the boundary as the initial fill
  // requires, and farther than insert * sigma from every node. Returns the nearest node (or -1).
  int accept_point(Vec2 p, int start) const {
    const std::optional<At> at = ruler_.at_inside(p);
    if (!at) return -1;
    const int v = ruler_.nearest(*at, p, start);
    if (!(ruler_.distance(*at, x(v), p) > t_.insert * at->unit)) return -1;
    if (ruler_.boundary_distance(*at, p) < kInitBoundaryClearance * at->unit) return -1;
    return v;
  }

  // Triangles whose circumradius exceeds insert * sigma, largest ratio first: a node at the
  // circumcentre, else at the midpoint of the longest edge.
  void vacancies() {
    std::vector<Vacancy> candidates = ruler_.large_triangles(t_.insert);
    std::sort(candidates.begin(), candidates.end(), [](const Vacancy& e, const Vacancy& f) {
      return e.ratio > f.ratio || (e.ratio == f.ratio && e.t < f.t);
    });
    const auto& tris = graph_.triangles;
    for (const Vacancy& cand : candidates) {
      const auto tri = tris[cand.t];
      if (used(tri[0]) || used(tri[1]) || used(tri[2])) continue;
      Vec2 p = cand.centre;
      int nearest = accept_point(p, tri[0]);
      if (nearest < 0) {
        int longest = 0;
        double best = -1.0;
        for (int k = 0; k < 3; ++k) {
          const double len = ruler_.edge_length(tri[k], tri[(k + 1) % 3]);
          if (len > best) {
            best = len;
            longest = k;
          }
        }
        p = 0.5 * (x(tri[longest]) + x(tri[(longest + 1) % 3]));
        nearest = accept_point(p, tri[0]);
      }
      if (nearest < 0 || used(nearest)) continue;
      plan_.interior_inserts.push_back(p);
      ++plan_.counts.inserted_interior;
      for (int v : tri) use(v);
      use_ring(nearest);
    }
  }

  static Vec2 point_at_arc(const Curve& curve, double arc) {
    const auto k = static_cast<std::size_t>(
        std::clamp<std::ptrdiff_t>(std::upper_bound(curve.arc.begin(), curve.arc.end(), arc) - curve.arc.begin() - 1, 0,
                                   static_cast<std::ptrdiff_t>(curve.points.size()) - 2));
    const double len = curve.arc[k + 1] - curve.arc[k];
    const double t = len > 0.0 ? std::clamp((arc - curve.arc[k]) / len, 0.0, 1.0) : 0.0;
    return curve.points[k] + t * (curve.points[k + 1] - curve.points[k]);
  }

  const NodeSet& nodes_;
  const std::vector<std::vector<double>>& arcs_;
  const GeometryTree& tree_;
  const Ruler& ruler_;
  const PopulationThresholds& t_;
  const DelaunayGraph& graph_;
  std::vector<char> used_;  // per node: 0 free, 1 taken by an operation, 2 end of a split gap (only splits share it)
  PopulationPlan plan_;
};

}  // namespace pdmesh::population_detail
