// What the operations of the cleanup in a metric share (metric_ops.hpp): the edge lists and the
// rule that keeps a split or a collapse.
#include "cleanup/metric_ops.hpp"

#include <algorithm>
#include <tuple>

namespace pdmesh::cleanup {

MetricOps::MetricOps(EditableMesh& mesh, const MetricEvaluator& metric, const Geometry& geometry,
                     MetricOpsOptions options)
    : m_(mesh), metric_(metric), geometry_(geometry), options_(options) {}

std::vector<MetricOps::Edge> MetricOps::edges_where(double above, double below) const {
  std::vector<Edge> out;
  for (int t = 0; t < m_.triangle_slots(); ++t) {
    if (!m_.alive(t)) continue;
    for (int i = 0; i < 3; ++i) {
      if (m_.n[t][i] >= 0 && m_.n[t][i] < t) continue;  // each interior edge from its higher triangle
      const int a = m_.v[t][next3(i)], b = m_.v[t][prev3(i)];
      const double l = metric_.length(a, b);
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
