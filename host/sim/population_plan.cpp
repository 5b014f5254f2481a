// Population-control planning: the Delaunay graph of the nodes, then the four rules in a fixed order
// (boundary gaps, clusters, low-valence nodes, vacancies), each node in at most one operation.
// Every loop runs in node, edge or sorted order with index tie-breaks, so a plan is reproducible.
#include "sim/population_plan.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "init/initial_distribution.hpp"
#include "mesh/delaunay.hpp"
#include "sim/delaunay_graph.hpp"

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

class Planner {
 public:
  Planner(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs, const GeometryTree& tree,
          const SpacingField& spacing, const PopulationThresholds& t)
      : nodes_(nodes), arcs_(arcs), tree_(tree), spacing_(spacing), t_(t), graph_(nodes.x), used_(nodes.size(), 0) {
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
  bool is(int i, NodeKind k) const { return nodes_.kind[static_cast<std::size_t>(i)] == k; }
  double q(int i) const { return nodes_.q[static_cast<std::size_t>(i)]; }
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
        const double sigma = 0.5 * (q(list[k - 1]) + q(list[k]));
        const double ratio = (arcs_[c][k] - arcs_[c][k - 1]) / sigma;
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
    const double qp = spacing_.at(p);
    // No other node (an interior node bulging into the gap) may be closer than a cluster.
    for (int end : {a, b})
      for (const int* u = graph_.begin(end); u != graph_.end(end); ++u)
        if (*u != a && *u != b && dist(x(*u), p) < t_.merge * qp) return;
    plan_.boundary_inserts.push_back({curve, k, arc});
    ++plan_.counts.inserted_boundary;
    used_[static_cast<std::size_t>(a)] = std::max<char>(used_[static_cast<std::size_t>(a)], 2);
    used_[static_cast<std::size_t>(b)] = std::max<char>(used_[static_cast<std::size_t>(b)], 2);
  }

  void close_gap(int curve, std::size_t k) {
    const auto c = static_cast<std::size_t>(curve);
    const std::vector<int>& list = nodes_.curve_nodes[c];
    const std::vector<double>& arcs = arcs_[c];
    // Candidates: list[k - 1] (merged gap arcs[k] - arcs[k - 2]) and list[k] (arcs[k + 1] - arcs[k - 1]).
    int best = -1;
    double best_ratio = t_.boundary_split;
    for (std::size_t m : {k - 1, k}) {
      if (m == 0 || m + 1 >= list.size() || !is(list[m], NodeKind::Boundary)) continue;
      const int before = list[m - 1], node = list[m], after = list[m + 1];
      if (used(before) || used(node) || used(after)) continue;
      const double ratio = (arcs[m + 1] - arcs[m - 1]) / (0.5 * (q(before) + q(after)));
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

  // Delaunay edges shorter than merge * sigma, shortest first: two interior nodes merge into their
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
        const double ratio = dist(x(a), x(b)) / (0.5 * (q(a) + q(b)));
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
  // requires, and farther than insert * q(p) from every node. Returns the nearest node (or -1).
  int accept_point(Vec2 p, int start, double& qp) const {
    qp = spacing_.at(p);
    if (!(qp > 0.0) || !std::isfinite(qp) || !tree_.inside(p)) return -1;
    const int v = graph_.nearest(nodes_.x, p, start);
    if (!(dist(x(v), p) > t_.insert * qp)) return -1;
    if (tree_.closest(p).distance < kInitBoundaryClearance * qp) return -1;
    return v;
  }

  // Triangles whose circumradius exceeds insert * q(circumcentre), largest ratio first: a node at
  // the circumcentre, else at the midpoint of the longest edge.
  void vacancies() {
    struct Candidate {
      double ratio;
      std::size_t t;
      Vec2 centre;
    };
    std::vector<Candidate> candidates;
    const auto& tris = graph_.triangles;
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
      if (!(radius > 0.75 * t_.insert * q_min)) continue;
      passed.push_back(t);
      centres.push_back(centre);
      radii.push_back(radius);
    }
    std::vector<double> qcs;
    spacing_.at_many(centres, qcs);
    for (std::size_t k = 0; k < passed.size(); ++k) {
      const double qc = qcs[k], radius = radii[k];
      if (!(qc > 0.0) || !(radius > t_.insert * qc)) continue;
      candidates.push_back({radius / qc, passed[k], centres[k]});
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& e, const Candidate& f) {
      return e.ratio > f.ratio || (e.ratio == f.ratio && e.t < f.t);
    });
    for (const Candidate& cand : candidates) {
      const auto tri = tris[cand.t];
      if (used(tri[0]) || used(tri[1]) || used(tri[2])) continue;
      double qp = 0.0;
      Vec2 p = cand.centre;
      int nearest = accept_point(p, tri[0], qp);
      if (nearest < 0) {
        int longest = 0;
        double best = -1.0;
        for (int k = 0; k < 3; ++k) {
          const double len = dist(x(tri[k]), x(tri[(k + 1) % 3]));
          if (len > best) {
            best = len;
            longest = k;
          }
        }
        p = 0.5 * (x(tri[longest]) + x(tri[(longest + 1) % 3]));
        nearest = accept_point(p, tri[0], qp);
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
  const SpacingField& spacing_;
  const PopulationThresholds& t_;
  DelaunayGraph graph_;
  std::vector<char> used_;  // per node: 0 free, 1 taken by an operation, 2 end of a split gap (only splits share it)
  PopulationPlan plan_;
};

}  // namespace

PopulationPlan plan_population_event(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs,
                                     const GeometryTree& tree, const SpacingField& spacing,
                                     const PopulationThresholds& thresholds) {
  return Planner(nodes, arcs, tree, spacing, thresholds).run();
}

}  // namespace pdmesh
