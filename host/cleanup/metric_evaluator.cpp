// The metric at the vertices of an editable mesh, metric lengths and Q (metric_evaluator.hpp).
#include "cleanup/metric_evaluator.hpp"

#include <cmath>

namespace pdmesh::cleanup {

double metric_mean_ratio(Vec2 a, Vec2 b, Vec2 c, const Metric& m) {
  const double area = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
  const double sum_l2 = m.quad(b - a) + m.quad(c - b) + m.quad(a - c);
  return sum_l2 > 0.0 ? 4.0 * std::sqrt(3.0) * area * std::sqrt(m.det()) / sum_l2 : -1.0;
}

MetricEvaluator::MetricEvaluator(const EditableMesh& mesh, const MetricField& field) : mesh_(mesh), field_(field) {}

const Metric& MetricEvaluator::at(int a) const {
  const auto k = static_cast<std::size_t>(a);
  if (k >= metric_.size()) {
    metric_.resize(k + 1);
    where_.resize(k + 1);
    known_.resize(k + 1, 0);
  }
  const Vec2 p = mesh_.p[a];
  if (!known_[k] || !(where_[k] == p)) {
    metric_[k] = field_.at(p);
    where_[k] = p;
    known_[k] = 1;
  }
  return metric_[k];
}

double MetricEvaluator::length(int a, int b) const {
  const Metric ma = at(a);
  return edge_length(ma, at(b), mesh_.p[b] - mesh_.p[a]);
}

double MetricEvaluator::length(Vec2 pa, const Metric& ma, Vec2 pb, const Metric& mb) const {
  return edge_length(ma, mb, pb - pa);
}

double MetricEvaluator::quality(Vec2 x, Vec2 y, Vec2 z, const Metric& mx, const Metric& my, const Metric& mz) {
  // The corner of largest det, the first on ties (mesh/metric_quality's rule).
  const Metric* pick = &mx;
  if (my.det() > pick->det()) pick = &my;
  if (mz.det() > pick->det()) pick = &mz;
  return metric_mean_ratio(x, y, z, *pick);
}

double MetricEvaluator::half_fraction(int a, int b) const {
  const Vec2 v = mesh_.p[b] - mesh_.p[a];
  const double la = at(a).length(v), lb = at(b).length(v);
  // The length element la r^s along the edge (r = lb / la): half the length at r^s = (1 + r) / 2.
  const double r = lb / la;
  if (!(la > 0.0) || !(lb > 0.0) || std::fabs(r - 1.0) <= 1e-6) return 0.5;
  return std::log(0.5 * (1.0 + r)) / std::log(r);
}

Vec2 MetricEvaluator::midpoint(int a, int b) const {
  const double s = half_fraction(a, b);
  return mesh_.p[a] + s * (mesh_.p[b] - mesh_.p[a]);
}

double MetricEvaluator::score(const EditableMesh& mesh, int t) const {
  const auto& tv = mesh.v[t];
  const Metric mx = at(tv[0]), my = at(tv[1]), mz = at(tv[2]);
  return quality(mesh.p[tv[0]], mesh.p[tv[1]], mesh.p[tv[2]], mx, my, mz);
}

}  // namespace pdmesh::cleanup
