// SizeSources: feature size and curvature evaluated at a point from its closest boundary point.
#include "spacing/size_sources.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "spacing/curvature.hpp"

namespace pdmesh {

SizeSources::SizeSources(const GeometryTree& tree, const SizeSourceOptions& options) : tree_(tree), options_(options) {
  feature_ = std::make_unique<FeatureSize>(tree.geometry());
  if (options_.curvature_angle > 0.0) {
    radius_ = segment_radii(tree.geometry());
    theta_ = options_.curvature_angle * M_PI / 180.0;
  }
}

double SizeSources::before_gap(Vec2 p, const ClosestHit& hit, double limit, double& floor,
                               FeatureSize::WidthQuery& query) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  const double s = options_.scale;
  // With input boundary points, no source asks for less than (a fraction of) the closest segment:
  // the first node row could not match the boundary row.
  floor = options_.input_boundary_floor * tree_.geometry().segments[static_cast<std::size_t>(hit.segment)].length;
  double q = kNone;
  if (theta_ > 0.0) {
    // The concentric circle at distance d from a curve of radius R has radius R + d: the same angle
    // theta there is (R + d) theta, a growth of theta per unit distance.
    const double r = radius_[static_cast<std::size_t>(hit.segment)];
    if (std::isfinite(r)) q = std::max(theta_ * (r + hit.distance), floor / s);
  }
  if (options_.rows_in_gap > 0.0) {
    // Only gaps narrower than k * limit / scale can ask for less than the limit.
    query.x = p;
    query.nearest = hit;
    query.inside = inside(p, hit);
    query.max_width = options_.rows_in_gap * std::min(limit, q * s) / s;
  }
  return q;
}

double SizeSources::after_gap(double q, double floor, double w, bool apart) const {
  const double s = options_.scale;
  const double k = options_.rows_in_gap;
  // Across a gap between two loops that never meet, or across a strait between two sides of one loop
  // that meet only far around it (FeatureSize::width's apart), boundary nodes placed by the field
  // need no floor: no sharp V tip asks for q -> 0 there, and a floor of the closest segment's length
  // would leave a gap beside a long segment unresolved.
  const bool floored = options_.final_floor || !apart;
  if (std::isfinite(w)) q = std::min(q, floored ? std::max(w / k, floor / s) : w / k);
  return q;
}

double SizeSources::at(Vec2 p, double limit, int* seed) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (!options_.active()) return kNone;
  const ClosestHit hit = feature_->closest(p, seed ? *seed : -1);
  if (seed) *seed = hit.segment;
  if (hit.segment < 0) return kNone;
  double floor = 0.0;
  FeatureSize::WidthQuery query;
  double q = before_gap(p, hit, limit, floor, query);
  if (options_.rows_in_gap > 0.0) {
    bool apart = false;
    const double w = feature_->width(query.x, query.nearest, query.inside, query.max_width, &apart);
    q = after_gap(q, floor, w, apart);
  }
  return options_.scale * q;
}

void SizeSources::at_many(const Vec2* p, const double* limit, std::size_t n, double* q,
                          FeatureSize::SearchSeed& seed) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (!options_.active()) {
    std::fill(q, q + n, kNone);
    return;
  }
  // A chunk at a time: the closest segments of its points, what comes before the gap searches, the
  // gap searches, the rest.
  constexpr std::size_t kChunk = 64;
  ClosestHit hit[kChunk];
  double floor[kChunk], width[kChunk];
  bool apart[kChunk];
  FeatureSize::WidthQuery query[kChunk];
  for (std::size_t first = 0; first < n; first += kChunk) {
    const std::size_t m = std::min(kChunk, n - first);
    feature_->closest_many(p + first, m, hit, seed);
    for (std::size_t i = 0; i < m; ++i) {
      query[i] = FeatureSize::WidthQuery{};  // no search where no segment was found
      if (hit[i].segment >= 0) q[first + i] = before_gap(p[first + i], hit[i], limit[first + i], floor[i], query[i]);
    }
    if (options_.rows_in_gap > 0.0) feature_->width_many(query, m, width, apart);
    for (std::size_t i = 0; i < m; ++i) {
      if (hit[i].segment < 0) {
        q[first + i] = kNone;
        continue;
      }
      if (options_.rows_in_gap > 0.0) q[first + i] = after_gap(q[first + i], floor[i], width[i], apart[i]);
      q[first + i] = options_.scale * q[first + i];
    }
  }
}

bool SizeSources::inside(Vec2 p, const ClosestHit& hit) const {
  // Beside an embedded constraint both sides are the domain's or neither: the tree decides.
  const Geometry& g = tree_.geometry();
  const bool open =
      hit.segment >= 0 &&
      g.curves[static_cast<std::size_t>(g.segments[static_cast<std::size_t>(hit.segment)].curve)].constraint;
  if (hit.distance > 0.0 && hit.t > 0.0 && hit.t < 1.0 && !open)
    return dot(p - hit.point, feature_->inward_normal(hit.segment)) > 0.0;
  return tree_.inside(p);
}

double SizeSources::floor_at(Vec2 p, double q) const {
  if (!has_floor()) return q;
  const double slope = kFloorSlope;
  // Between the upper envelope of downward cones and the lower envelope of upward ones: at the
  // boundary exactly the segment's own length unless a shorter segment is near, and slope-Lipschitz.
  double floor = feature_->segment_envelope(p, options_.input_boundary_floor, slope, q);
  if (!(floor > q)) return q;
  const double lower = feature_->segment_lower_envelope(p, options_.input_boundary_floor, slope);
  return std::max(q, std::min(floor, lower));
}

}  // namespace pdmesh
