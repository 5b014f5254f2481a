// What the operations of the cleanup in a metric share (metric_ops.hpp): the edges' measure, the edge
// lists and the rule that keeps a split or a collapse.
#include "cleanup/metric_ops.hpp"

#include <algorithm>
#include <tuple>

#include "spacing/curve_metric_length.hpp"

namespace pdmesh::cleanup {

MetricOps::MetricOps(EditableMesh& mesh, const MetricEvaluator& metric, const Geometry& geometry,
                     MetricOpsOptions options)
    : m_(mesh), metric_(metric), geometry_(geometry), options_(options) {}

double MetricOps::measure(int t, int i) const {
  const double chord = metric_.length(m_.v[t][next3(i)], m_.v[t][prev3(i)]);
  if (m_.n[t][i] >= 0) return chord;
  int c = -1;
  double arc_a = 0.0, arc_b = 0.0;
  if (!m_.boundary_edge_arcs(t, i, c, arc_a, arc_b)) return chord;
  return std::max(chord,
                  curve_metric_length(geometry_.curves[static_cast<std::size_t>(c)], metric_.field(), arc_a, arc_b));
}

double MetricOps::measure_between(int a, int b) const {
  std::array<int, 2> edge = m_.find_edge(a, b);
  if (edge[0] < 0) edge = m_.find_edge(b, a);
  return edge[0] < 0 ? metric_.length(a, b) : measure(edge[0], edge[1]);
}

std::vector<MetricOps::Edge> MetricOps::edges_where(double above, double below) const {
  std::vector<Edge> out;
  for (int t = 0; t < m_.triangle_slots(); ++t) {
    if (!m_.alive(t)) continue;
    for (int i = 0; i < 3; ++i) {
      if (m_.n[t][i] >= 0 && m_.n[t][i] < t) continue;  // each interior edge from its higher triangle
      const int a = m_.v[t][next3(i)], b = m_.v[t][prev3(i)];
      const double l = measure(t, i);
      if (l > above || l < below) out.push_back({l, std::min(a, b), std::max(a, b)});
    }
  }
  return out;
}

bool MetricOps::keep_edit() const {
  const double before = m_.touched_min_before(), after = m_.touched_min_after();
  return after > 0.0 && (after >= options_.keep_ratio * before || after >= options_.keep_floor);
}

}  // namespace pdmesh::cleanup
