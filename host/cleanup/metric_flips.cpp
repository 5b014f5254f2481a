// Flips of the cleanup in a metric: an interior edge whose quadrilateral is strictly convex in
// physical space (exact orient2d) is flipped when the two new triangles' smallest Q is above the two
// old ones', unless the new edge's metric length is outside the window [1/√2, √2] and the old one's
// inside. Each flip raises the smallest Q of its quadrilateral, so no flip is undone and the passes end.
// A pass tests only the edges whose triangles changed since the pass before (the editable mesh's
// triangle marks).
#include <algorithm>
#include <cmath>

#include "cleanup/metric_ops.hpp"
#include "core/predicates.hpp"

namespace pdmesh::cleanup {
namespace {

// A flip must raise the quadrilateral's smallest Q by more than this (relative), so that rounding
// cannot make two diagonals each look better than the other.
constexpr double kFlipGain = 1e-9;

}  // namespace

bool MetricOps::flip_if_better(int t, int i) {
  const int u = m_.n[t][i];
  if (u < 0) return false;
  const int pv = m_.v[t][i], a = m_.v[t][next3(i)], b = m_.v[t][prev3(i)];
  const int q = m_.v[u][EditableMesh::index_of(m_.n[u], t)];
  const Vec2 P = m_.p[pv], A = m_.p[a], B = m_.p[b], Q = m_.p[q];
  if (!(orient2d(P, A, Q) > 0.0) || !(orient2d(Q, B, P) > 0.0)) return false;
  const double old_min = std::min(m_.quality(t), m_.quality(u));
  const Metric mp = metric_.at(pv), ma = metric_.at(a), mb = metric_.at(b), mq = metric_.at(q);
  const double new_min =
      std::min(MetricEvaluator::quality(P, A, Q, mp, ma, mq), MetricEvaluator::quality(Q, B, P, mq, mb, mp));
  if (!(new_min > old_min + kFlipGain * std::fabs(old_min))) return false;
  // Not when it trades an edge in the window for one outside it.
  const double old_l = metric_.length(a, b), new_l = metric_.length(pv, q);
  const auto outside = [](double l) { return l < kMetricShort || l > kMetricLong; };
  if (outside(new_l) && !outside(old_l)) return false;
  m_.flip(t, i);
  return true;
}

std::size_t MetricOps::flip_all(int max_rounds) {
  std::size_t made = 0;
  for (int round = 0; round < max_rounds; ++round) {
    // Every pass tests each edge or knows its answer: an edge whose two triangles were not marked since
    // the last pass began (same points, metrics, scores and neighbours) was found not to flip then or
    // later, and would be again. So only the changed edges are tested, with the same flips as testing all.
    const std::uint32_t since = flip_pass_epoch_;
    m_.next_epoch();
    flip_pass_epoch_ = m_.epoch();
    std::size_t now = 0;
    for (int t = 0; t < m_.triangle_slots(); ++t) {
      if (!m_.alive(t)) continue;
      const bool t_changed = m_.triangle_marked_in(t, since);
      for (int i = 0; i < 3; ++i) {
        const int u = m_.n[t][i];
        if (u <= t || (!t_changed && !m_.triangle_marked_in(u, since))) continue;
        if (flip_if_better(t, i)) ++now;
      }
    }
    made += now;
    if (now == 0) break;
  }
  counts_.flips += made;
  return made;
}

}  // namespace pdmesh::cleanup
