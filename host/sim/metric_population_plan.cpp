// Population-control planning in a metric field (sim/population_plan.hpp, plan_metric_population_event):
// the isotropic planner's four rules with every length measured in the metric, sigma = 1 in metric
// units, on the nodes' Delaunay graph in the metric (mesh/metric_delaunay). Every loop runs in node,
// edge or sorted order with index tie-breaks, so a plan is reproducible.
#include <algorithm>
#include <cmath>
#include <tuple>

#include "init/boundary_placement.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/delaunay.hpp"
#include "mesh/metric_delaunay.hpp"
#include "sim/delaunay_graph.hpp"
#include "sim/population_plan.hpp"
#include "spacing/metric_field.hpp"

namespace pdmesh {
namespace {

using population_detail::DelaunayGraph;

// The nodes' triangulation flipped to the metric's Delaunay (metrics[i] at node i).
DelaunayGraph metric_graph(const std::vector<Vec2>& x, const std::vector<Metric>& metrics) {
  Triangulation dt(x);
  make_metric_delaunay(dt, metrics);
  return DelaunayGraph(dt);
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

class MetricPlanner {
 public:
  MetricPlanner(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs, const GeometryTree& tree,
                const MetricField& metric, const PopulationThresholds& t)
      : nodes_(nodes),
        arcs_(arcs),
        tree_(tree),
        metric_(metric),
        t_(t),
        m_(metrics(nodes, metric)),
        graph_(metric_graph(nodes.x, m_)),
        used_(nodes.size(), 0) {
    plan_.remove.assign(nodes.size(), 0);
  }

  PopulationPlan run() {
    if (t_.boundary) boundary_gaps();
    clusters();
    if (t_.remove_valence > 0) low_valence();
    vacancies();
    return std::move(plan_);
  }

 private:
  static std::vector<Metric> metrics(const NodeSet& nodes, const MetricField& metric) {
    std::vector<Metric> m(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) m[i] = metric.at(nodes.x[i]);
    return m;
  }
  bool is(int i, NodeKind k) const { return nodes_.kind[static_cast<std::size_t>(i)] == k; }
  Vec2 x(int i) const { return nodes_.x[static_cast<std::size_t>(i)]; }
  const Metric& m(int i) const { return m_[static_cast<std::size_t>(i)]; }
  // The metric length of the edge between nodes a and b (UGAWG's, spacing/metric.hpp).
  double length(int a, int b) const { return edge_length(m(a), m(b), x(b) - x(a)); }
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

  // Boundary gaps by the metric length of their chord: long ones get a node at their middle (longest
  // first); short ones lose a Boundary node (shortest first) when the gap that results stays below the
  // split threshold.
  void boundary_gaps() {
    struct Gap {
      double length;
      int curve;
      std::size_t k;
    };
    std::vector<Gap> long_gaps, short_gaps;
    for (std::size_t c = 0; c < nodes_.curve_nodes.size(); ++c) {
      const std::vector<int>& list = nodes_.curve_nodes[c];
      for (std::size_t k = 1; k < list.size(); ++k) {
        const double len = length(list[k - 1], list[k]);
        if (len > t_.boundary_split) long_gaps.push_back({len, static_cast<int>(c), k});
        if (len < t_.merge) short_gaps.push_back({len, static_cast<int>(c), k});
      }
    }
    const auto order = [](const Gap& a, const Gap& b) {
      return std::tie(a.length, a.curve, a.k) < std::tie(b.length, b.curve, b.k);
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
    if (used_[static_cast<std::size_t>(a)] == 1 || used_[static_cast<std::size_t>(b)] == 1) return;
    const double arc = 0.5 * (arcs_[c][k - 1] + arcs_[c][k]);
    if (!(arcs_[c][k - 1] < arc && arc < arcs_[c][k])) return;
    const Curve& geometry_curve = tree_.geometry().curves[c];
    if (geometry_curve.fixed_points) return;
    const Vec2 p = point_at_arc(geometry_curve, arc);
    const Metric mp = metric_.at(p);
    for (int end : {a, b})
      for (const int* u = graph_.begin(end); u != graph_.end(end); ++u)
        if (*u != a && *u != b && mp.length(x(*u) - p) < t_.merge) return;
    plan_.boundary_inserts.push_back({curve, k, arc});
    ++plan_.counts.inserted_boundary;
    used_[static_cast<std::size_t>(a)] = std::max<char>(used_[static_cast<std::size_t>(a)], 2);
    used_[static_cast<std::size_t>(b)] = std::max<char>(used_[static_cast<std::size_t>(b)], 2);
  }

  void close_gap(int curve, std::size_t k) {
    const auto c = static_cast<std::size_t>(curve);
    const std::vector<int>& list = nodes_.curve_nodes[c];
    int best = -1;
    double best_length = t_.boundary_split;
    for (std::size_t j : {k - 1, k}) {
      if (j == 0 || j + 1 >= list.size() || !is(list[j], NodeKind::Boundary)) continue;
      const int before = list[j - 1], node = list[j], after = list[j + 1];
      if (used(before) || used(node) || used(after)) continue;
      const double len = length(before, after);
      if (len < best_length) {
        best_length = len;
        best = static_cast<int>(j);
      }
    }
    if (best < 0) return;
    const auto j = static_cast<std::size_t>(best);
    remove(list[j]);
    use(list[j - 1]);
    use(list[j + 1]);
    ++plan_.counts.removed_boundary;
  }

  // Graph edges shorter than merge in the metric, shortest first: two interior nodes merge into their
  // midpoint; an interior node next to a boundary or fixed node leaves.
  void clusters() {
    struct Edge {
      double length;
      int a, b;
    };
    std::vector<Edge> short_edges;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const int a = static_cast<int>(i);
      for (const int* u = graph_.begin(a); u != graph_.end(a); ++u) {
        const int b = *u;
        if (b <= a || (!is(a, NodeKind::Interior) && !is(b, NodeKind::Interior))) continue;
        const double len = length(a, b);
        if (len < t_.merge) short_edges.push_back({len, a, b});
      }
    }
    std::sort(short_edges.begin(), short_edges.end(),
              [](const Edge& e, const Edge& f) { return std::tie(e.length, e.a, e.b) < std::tie(f.length, f.a, f.b); });
    for (const Edge& e : short_edges) {
      if (used(e.a) || used(e.b)) continue;
      const bool a_in = is(e.a, NodeKind::Interior), b_in = is(e.b, NodeKind::Interior);
      if (a_in && b_in) {
        if (tree_.crosses_boundary(x(e.a), x(e.b))) continue;
        plan_.moves.emplace_back(e.a, 0.5 * (x(e.a) + x(e.b)));
        remove(e.b);
        use(e.a);
        ++plan_.counts.merged;
      } else {
        const int inner = a_in ? e.a : e.b, outer = a_in ? e.b : e.a;
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

  // The node nearest to p in the metric mp, by a greedy walk over the graph from `start`.
  int nearest(const Metric& mp, Vec2 p, int start) const {
    int v = start;
    double best = mp.quad(x(v) - p);
    for (;;) {
      int next = v;
      for (const int* u = graph_.begin(v); u != graph_.end(v); ++u) {
        const double d = mp.quad(x(*u) - p);
        if (d < best) {
          best = d;
          next = *u;
        }
      }
      if (next == v) return v;
      v = next;
    }
  }

  // Whether p can take a new interior node: inside, at least kInitBoundaryClearance from the closest
  // boundary point and farther than insert from every node, in the metric at p. Returns the nearest
  // node (or -1).
  int accept_point(Vec2 p, int start) const {
    if (!tree_.inside(p)) return -1;
    const Metric mp = metric_.at(p);
    const int v = nearest(mp, p, start);
    if (!(mp.length(x(v) - p) > t_.insert)) return -1;
    if (mp.length(tree_.closest(p).point - p) < kInitBoundaryClearance) return -1;
    return v;
  }

  // Triangles whose circumradius in their mean metric exceeds insert, largest first: a node at the
  // circumcentre, else at the midpoint of the longest edge in the metric.
  void vacancies() {
    struct Candidate {
      double radius;
      std::size_t t;
      Vec2 centre;
    };
    std::vector<Candidate> candidates;
    const auto& tris = graph_.triangles;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const auto [a, b, c] = tris[t];
      const Metric mean = (1.0 / 3.0) * (m(a) + m(b) + m(c));
      Vec2 centre;
      double radius = 0.0;
      metric_circumcircle(mean, x(a), x(b), x(c), centre, radius);
      if (radius > t_.insert) candidates.push_back({radius, t, centre});
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& e, const Candidate& f) {
      return e.radius > f.radius || (e.radius == f.radius && e.t < f.t);
    });
    for (const Candidate& cand : candidates) {
      const auto tri = tris[cand.t];
      if (used(tri[0]) || used(tri[1]) || used(tri[2])) continue;
      Vec2 p = cand.centre;
      int near = accept_point(p, tri[0]);
      if (near < 0) {
        int longest = 0;
        double best = -1.0;
        for (int k = 0; k < 3; ++k) {
          const double len = length(tri[k], tri[(k + 1) % 3]);
          if (len > best) {
            best = len;
            longest = k;
          }
        }
        p = 0.5 * (x(tri[longest]) + x(tri[(longest + 1) % 3]));
        near = accept_point(p, tri[0]);
      }
      if (near < 0 || used(near)) continue;
      plan_.interior_inserts.push_back(p);
      ++plan_.counts.inserted_interior;
      for (int v : tri) use(v);
      use_ring(near);
    }
  }

  const NodeSet& nodes_;
  const std::vector<std::vector<double>>& arcs_;
  const GeometryTree& tree_;
  const MetricField& metric_;
  const PopulationThresholds& t_;
  std::vector<Metric> m_;  // per node
  DelaunayGraph graph_;
  std::vector<char> used_;  // as in the isotropic planner
  PopulationPlan plan_;
};

}  // namespace

PopulationPlan plan_metric_population_event(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs,
                                            const GeometryTree& tree, const MetricField& metric,
                                            const PopulationThresholds& thresholds) {
  return MetricPlanner(nodes, arcs, tree, metric, thresholds).run();
}

}  // namespace pdmesh
