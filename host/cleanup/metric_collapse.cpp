// Edge collapses of the cleanup in a metric: an edge shorter than collapse_below in the metric loses
// one of its ends into the other. An interior node may go into any neighbour, which stays where it is or,
// when it is interior too, moves to the edge's metric midpoint; a boundary node only into its
// neighbour along its curve, which stays; fixed nodes never go. Of these collapses the one that
// leaves the best smallest Q is made, when the kept node's star is counter-clockwise (exact
// orient2d), its longest edge is no longer than collapse_max_length or than the longest edge of the
// two ends before, and keep_edit() holds.
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "cleanup/metric_ops.hpp"
#include "geometry/curve_projection.hpp"

namespace pdmesh::cleanup {

std::size_t MetricOps::collapse_short() {
  const double below = options_.collapse_below;
  std::vector<Edge> edges = edges_where(std::numeric_limits<double>::infinity(), below);
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return std::tie(x.length, x.a, x.b) < std::tie(y.length, y.a, y.b);  // shortest first
  });
  std::size_t made = 0;
  for (const Edge& e : edges) {
    if (m_.removed(e.a) || m_.removed(e.b)) continue;
    if (!(measure_between(e.a, e.b) < below)) continue;  // an earlier edit lengthened it
    made += collapse_edge(e.a, e.b) ? 1 : 0;
  }
  return made;
}

double MetricOps::longest_edge(int a, int skip) {
  m_.ring(a, ring_);
  double longest = 0.0;
  for (int x : ring_)
    if (x != skip) longest = std::max(longest, metric_.length(a, x));
  return longest;
}

bool MetricOps::centre_on_curve(int a) {
  const int before = m_.prev[a], after = m_.next[a];
  const double lo = m_.neighbour_arc(a, 0), hi = m_.neighbour_arc(a, 1);
  if (!std::isfinite(lo) || !std::isfinite(hi)) return false;
  const double at_arc = lo + metric_.half_fraction(before, after) * (hi - lo);
  if (!(at_arc > lo && at_arc < hi)) return false;
  m_.move(a, closest_on_curve_range(geometry_.curves[m_.curve[a]], {}, at_arc, at_arc).p, at_arc);
  return true;
}

bool MetricOps::collapse_edge(int a, int b) {
  const double limit = std::max(options_.collapse_max_length, std::max(longest_edge(a, b), longest_edge(b, a)));
  const Vec2 mid = metric_.midpoint(a, b);
  // Removes `gone` into `kept` (moved to the midpoint when `to_mid`) in an open transaction; false
  // (rolled back) when not allowed.
  auto attempt = [&](int gone, int kept, bool to_mid) {
    const auto [t, i] = m_.find_edge(gone, kept);
    const auto [u, j] = m_.find_edge(kept, gone);
    if (t < 0 && u < 0) return false;
    const bool on_boundary = t < 0 || u < 0;
    bool made = false;
    m_.begin();
    if (m_.kind[gone] == NodeKind::Interior && !on_boundary)
      made = m_.collapse(gone, kept, to_mid ? mid : m_.p[kept], m_.arc[kept]);
    else if (m_.kind[gone] == NodeKind::Boundary && on_boundary)
      made = m_.collapse_boundary(gone, kept) && (!to_mid || centre_on_curve(kept));
    if (!made || !m_.star_valid(kept) || !(longest_edge(kept, -1) <= limit) || !keep_edit()) {
      m_.rollback();
      return false;
    }
    return true;
  };
  // Trials: a into b, b into a (each staying), then the same moving to the middle: the metric
  // midpoint for two interior nodes, the middle of its new curve neighbours for a boundary node.
  double best = -std::numeric_limits<double>::infinity();
  int choice = -1;
  for (int k = 0; k < 4; ++k) {
    const int gone = k % 2 == 1 ? b : a, kept = k % 2 == 1 ? a : b;
    const bool to_mid = k >= 2;
    if (to_mid && (m_.kind[kept] != m_.kind[gone] || m_.kind[kept] == NodeKind::Fixed)) continue;
    if (k == 3 && m_.kind[kept] == NodeKind::Interior) continue;  // the midpoint is the same either way
    if (!attempt(gone, kept, to_mid)) continue;
    const double q = m_.touched_min_after();
    m_.rollback();
    if (q > best) {
      best = q;
      choice = k;
    }
  }
  if (choice < 0) return false;
  const int gone = choice % 2 == 1 ? b : a, kept = choice % 2 == 1 ? a : b;
  const bool boundary = m_.kind[gone] == NodeKind::Boundary;
  attempt(gone, kept, choice >= 2);  // deterministic: the same edit as measured
  m_.commit();
  ++(boundary ? counts_.boundary_collapses : counts_.collapses);
  return true;
}

}  // namespace pdmesh::cleanup
