// BoundarySpacing: thesis eq. 3.6, q = sum_s(l_s/d_s) / sum_s(1/d_s) over the closest segment s of
// each curve, with its continuous limit on the boundary (see docs/spacing.md).
#include <algorithm>
#include <vector>

#include "core/parallel.hpp"

#include "spacing/spacing_field.hpp"

namespace pdmesh {

BoundarySpacing::BoundarySpacing(const GeometryTree& tree) : tree_(tree) {}

namespace {

// eq. 3.6 at p. `hits` carries the previous query's answer of the same thread as the seed of this one's
// searches: at_many's batches are spatially ordered (cell corners and test points level by level), so
// the last segment is usually the answer or close to it. The result does not depend on the seed
// (GeometryTree::closest_per_curve_near).
double boundary_spacing_at(const GeometryTree& tree, Vec2 p, std::vector<ClosestHit>& hits) {
  tree.closest_per_curve_near(p, hits);
  const auto& segs = tree.geometry().segments;
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

}  // namespace

double BoundarySpacing::at(Vec2 p) const {
  // No seed kept between calls (a thread_local would be; see parallel_for_scratch for why not): the
  // batches go through at_many.
  std::vector<ClosestHit> hits;
  return boundary_spacing_at(tree_, p, hits);
}

void BoundarySpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  // Every point is independent, so the values are at()'s whatever the thread count; each thread's
  // previous answer seeds its next searches. A point costs about 3 us on 30P30N (15 curve searches),
  // so 512 points (1.5 ms) are worth a thread (~50 us to start): with 4096, 35k of the 263k points of
  // the thesis 30P30N quadtree, in its small early and late batches, were evaluated on one core.
  parallel_for_scratch<std::vector<ClosestHit>>(
      p.size(), [&](std::vector<ClosestHit>& hits, std::size_t i) { q[i] = boundary_spacing_at(tree_, p[i], hits); },
      512, kMaxThreads);
}

}  // namespace pdmesh
