// BoundarySpacing: thesis eq. 3.6, q = sum_s(l_s/d_s) / sum_s(1/d_s) over the closest segment s of
// each curve, with its continuous limit on the boundary (see docs/spacing.md).
#include <algorithm>
#include <vector>

#include "core/parallel.hpp"

#include "spacing/spacing_field.hpp"

namespace pdmesh {

BoundarySpacing::BoundarySpacing(const GeometryTree& tree) : tree_(tree) {}

namespace {

// eq. 3.6 from each curve's closest segment: segment(c) (-1 for a curve without one) at distance(c),
// c in [0, curves), summed in curve order.
template <class SegmentOf, class DistanceOf>
double eq36(const std::vector<Segment>& segs, std::size_t curves, SegmentOf segment, DistanceOf distance) {
  double d_min = -1.0;
  for (std::size_t c = 0; c < curves; ++c)
    if (segment(c) >= 0 && (d_min < 0.0 || distance(c) < d_min)) d_min = distance(c);
  if (d_min < 0.0) return 0.0;  // no segments at all: nothing to weight
  // Multiplying numerator and denominator by d_min gives weights d_min/d_s in (0, 1], which cannot
  // overflow however small d_min is. At d_min == 0 the weights become 1 for the curves at distance 0
  // and 0 for the others: exactly the limit of eq. 3.6, so q is continuous onto the boundary.
  double num = 0.0;
  double den = 0.0;
  for (std::size_t c = 0; c < curves; ++c) {
    const int s = segment(c);
    if (s < 0) continue;
    const double d = distance(c);
    const double w = d_min == 0.0 ? (d == 0.0 ? 1.0 : 0.0) : d_min / d;
    num += w * segs[static_cast<std::size_t>(s)].length;
    den += w;
  }
  return num / den;
}

// eq. 3.6 at p. `hits` carries the previous query's answer of the same thread as the seed of this one's
// searches. The result does not depend on the seed (GeometryTree::closest_per_curve_near).
double boundary_spacing_at(const GeometryTree& tree, Vec2 p, std::vector<ClosestHit>& hits) {
  tree.closest_per_curve_near(p, hits);
  return eq36(
      tree.geometry().segments, hits.size(), [&](std::size_t c) { return hits[c].segment; },
      [&](std::size_t c) { return hits[c].distance; });
}

}  // namespace

double BoundarySpacing::at(Vec2 p) const {
  // No seed kept between calls (a thread_local would be; see parallel_for_scratch for why not): the
  // batches go through at_many.
  std::vector<ClosestHit> hits;
  return boundary_spacing_at(tree_, p, hits);
}

namespace {

// Points per block of at_many: each curve is searched for the whole block before the next curve.
constexpr std::size_t kBlock = 64;

// A thread's state between blocks: the last answer per curve (the next block's seeds) and the
// block's per-curve distances and segments.
struct BlockScratch {
  std::vector<int> seed;
  std::vector<double> distance;  // curve c's distance to point i of the block at c * kBlock + i
  std::vector<int> segment;
};

}  // namespace

void BoundarySpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  const auto curves = static_cast<std::size_t>(tree_.curve_count());
  const auto& segs = tree_.geometry().segments;
  const std::size_t blocks = (p.size() + kBlock - 1) / kBlock;
  // Every point is independent, so the values are at()'s whatever the thread count or the blocks; each
  // curve's previous answer seeds its next search. Curve by curve over a block of points rather than
  // point by point over the curves: one curve's tree stays in the first-level cache and its search
  // takes the same branches from one point to the next. eq. 3.6 is then summed per point in curve
  // order by the same eq36 as at(). A point costs about 3 us on 30P30N (15 curve searches),
  // so 512 points (1.5 ms) are worth a thread (~50 us to start): with 4096, 35k of the 263k points of
  // the thesis 30P30N quadtree, in its small early and late batches, were evaluated on one core.
  parallel_for_scratch<BlockScratch>(
      blocks,
      [&](BlockScratch& scratch, std::size_t b) {
        if (scratch.seed.size() != curves) {
          scratch.seed.assign(curves, -1);
          scratch.distance.resize(curves * kBlock);
          scratch.segment.resize(curves * kBlock);
        }
        const std::size_t first = b * kBlock;
        const std::size_t n = std::min(kBlock, p.size() - first);
        for (std::size_t c = 0; c < curves; ++c)
          tree_.closest_on_curve_many(&p[first], n, static_cast<int>(c), &scratch.distance[c * kBlock],
                                      &scratch.segment[c * kBlock], &scratch.seed[c]);
        for (std::size_t i = 0; i < n; ++i)
          q[first + i] = eq36(
              segs, curves, [&](std::size_t c) { return scratch.segment[c * kBlock + i]; },
              [&](std::size_t c) { return scratch.distance[c * kBlock + i]; });
      },
      512 / kBlock, kMaxThreads);
}

}  // namespace pdmesh
