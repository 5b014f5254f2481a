// Edge splits of the cleanup in a metric: an edge longer than √2 in the metric gets a node at its
// metric midpoint; a boundary edge's node goes on its curve, at the same fraction of the arc, or at the
// curve's metric middle where the curve is longer in the metric than the chord (a boundary edge is
// measured by the longer of the two, MetricOps::measure).
#include <algorithm>
#include <tuple>

#include "cleanup/metric_ops.hpp"
#include "core/predicates.hpp"
#include "geometry/curve_projection.hpp"
#include "spacing/curve_metric_length.hpp"

namespace pdmesh::cleanup {

std::size_t MetricOps::split_long() {
  std::vector<Edge> edges = edges_where(kMetricLong, -1.0);
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return std::tie(y.length, x.a, x.b) < std::tie(x.length, y.a, y.b);  // longest first
  });
  std::size_t made = 0;
  for (const Edge& e : edges) {
    if (m_.removed(e.a) || m_.removed(e.b)) continue;
    if (!(measure_between(e.a, e.b) > kMetricLong)) continue;  // an earlier edit shortened it
    made += split_edge(e.a, e.b) ? 1 : 0;
  }
  return made;
}

bool MetricOps::split_edge(int a, int b) {
  std::array<int, 2> edge = m_.find_edge(a, b);
  if (edge[0] < 0) edge = m_.find_edge(b, a);
  const int t = edge[0], i = edge[1];
  if (t < 0) return false;
  const int ea = m_.v[t][next3(i)], eb = m_.v[t][prev3(i)];
  const bool boundary = m_.n[t][i] < 0;
  if (!boundary) {
    const Vec2 at = metric_.midpoint(ea, eb);
    if (!m_.split_edge_valid(t, i, at)) return false;
    m_.begin();
    m_.split_edge(t, i, at);
  } else {
    if (!options_.split_boundary) return false;
    int c = -1;
    double arc_a = 0.0, arc_b = 0.0;
    if (!m_.boundary_edge_arcs(t, i, c, arc_a, arc_b)) return false;
    const Curve& curve = geometry_.curves[c];
    if (curve.fixed_points) return false;  // a layer front: the layer cells share its edges
    // The curve's metric middle where the curve is longer in the metric than the chord, else the
    // chord's metric midpoint carried to the arc.
    const double along = curve_metric_length(curve, metric_.field(), arc_a, arc_b);
    const double at_arc = along > metric_.length(ea, eb) ? curve_metric_half(curve, metric_.field(), arc_a, arc_b)
                                                         : arc_a + metric_.half_fraction(ea, eb) * (arc_b - arc_a);
    if (!(at_arc > std::min(arc_a, arc_b) && at_arc < std::max(arc_a, arc_b))) return false;
    const Vec2 at = closest_on_curve_range(curve, {}, at_arc, at_arc).p;
    const Vec2 x = m_.p[m_.v[t][i]];
    if (!(orient2d(x, m_.p[ea], at) > 0.0 && orient2d(x, at, m_.p[eb]) > 0.0)) return false;
    m_.begin();
    m_.split_boundary_edge(t, i, at, at_arc, c);
  }
  if (!keep_edit()) {
    m_.rollback();
    return false;
  }
  m_.commit();
  ++(boundary ? counts_.boundary_splits : counts_.splits);
  return true;
}

}  // namespace pdmesh::cleanup
