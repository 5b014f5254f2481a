// BoundarySpacing: thesis eq. 3.6, q = sum_s(l_s/d_s) / sum_s(1/d_s) over the closest segment s of
// each curve, with its continuous limit on the boundary (see docs/spacing.md).
#include <vector>

#include "spacing/spacing_field.hpp"

namespace pdmesh {

BoundarySpacing::BoundarySpacing(const GeometryTree& tree) : tree_(tree) {}

double BoundarySpacing::at(Vec2 p) const {
  thread_local std::vector<ClosestHit> hits;
  tree_.closest_per_curve(p, hits);
  const auto& segs = tree_.geometry().segments;
  double d_min = -1.0;
  for (const ClosestHit& h : hits)
    if (h.segment >= 0 && (d_min < 0.0 || h.distance < d_min)) d_min = h.distance;
  if (d_min < 0.0) return 0.0;  // no segments at all: nothing to weight
  // Multiplying numerator and denominator by d_min gives weights d_min/d_s in (0, 1], which cannot
  // overflow however small d_min is. At d_min == 0 the weights become 1 for the curves at distance 0
  // and 0 for the others: exactly the limit of eq. 3.6, so q is continuous onto the boundary.
  double num = 0.0;
  double den = 0.0;
  for (const ClosestHit& h : hits) {
    if (h.segment < 0) continue;
    double w;
    if (d_min == 0.0) {
      w = h.distance == 0.0 ? 1.0 : 0.0;
    } else {
      w = d_min / h.distance;
    }
    num += w * segs[h.segment].length;
    den += w;
  }
  return num / den;
}

void BoundarySpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  // Every point is independent and at() is thread-safe: the same values as one loop.
  for_chunks(p.size(), kMaxThreads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) q[i] = at(p[i]);
  });
}

}  // namespace pdmesh
