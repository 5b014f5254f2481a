#include "app/pipeline/layer_metric.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "spacing/metric.hpp"

namespace pdmesh {

namespace {

// Under a metric field the wall nodes follow the metric along the wall: a wall curve keeps those of
// its points that make chords of about this metric length (its critical points always), so that
// the layer's front, whose edges are about its wall edges, is near the unit-mesh window along the
// wall instead of at the input's spacing.
constexpr double kWallChordMetricLength = 1.0;
// A chord may be up to this much longer where that brings it nearer to kWallChordMetricLength than
// the chord a point shorter.
constexpr double kWallChordStretch = 1.25;
// ... as far as the wall's curvature allows: a chord turns from the chord before it, and from each
// input segment it replaces, by at most this many degrees (below the 10 at which a triangle layer's
// vertex gets a fan), and the points it drops lie within this metric distance of it.
constexpr double kWallChordTurnDeg = 8.0;
constexpr double kWallChordSagitta = 0.1;

// The points of a wall curve under `metric`: those of `curve`'s points that make chords of about unit
// metric length (its first and last point and its critical points always), and input segments longer
// than that split into equal parts of about unit length. A chord's
// metric length is the sum of the input segments it replaces, each measured in the metric at the wall
// and at `offset` along its normal into the domain (`domain`: where the layer's front will be), the
// longer of the two, so that a metric that changes across the layer (a solution's shear layer along the wall)
// is seen at the front too.
std::vector<Vec2> wall_stations(const Curve& curve, const GeometryTree& domain, const MetricField& metric,
                                double offset) {
  const std::vector<Vec2>& p = curve.points;
  const std::size_t n = p.size();
  std::vector<Metric> m(n);
  for (std::size_t i = 0; i < n; ++i) m[i] = metric.at(p[i]);
  // segment[i]: the metric length of the input segment i -> i + 1.
  std::vector<double> segment(n > 0 ? n - 1 : 0);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Vec2 v = p[i + 1] - p[i];
    const Vec2 unit_normal = Vec2{-v.y, v.x} * (1.0 / std::hypot(v.x, v.y));
    // The normal towards the domain (the side the layer grows into), probed a hundredth of the
    // segment off its midpoint.
    const Vec2 probe = (p[i] + p[i + 1]) * 0.5 + unit_normal * (0.01 * std::hypot(v.x, v.y));
    const Vec2 normal = unit_normal * (domain.inside(probe) ? offset : -offset);
    segment[i] = std::max(edge_length(m[i], m[i + 1], v),
                          edge_length(metric.at(p[i] + normal), metric.at(p[i + 1] + normal), v));
  }
  const double max_turn = kWallChordTurnDeg * std::numbers::pi / 180.0;
  const auto turn = [](Vec2 a, Vec2 b) { return std::fabs(std::atan2(cross(a, b), dot(a, b))); };
  Vec2 before{0.0, 0.0};  // the chord before (none at the curve's start)
  // Whether the chord k -> j may replace the input points between them.
  const auto fits = [&](std::size_t k, std::size_t j) {
    const Vec2 c = p[j] - p[k];
    const double lc = std::hypot(c.x, c.y);
    double length = 0.0;
    for (std::size_t i = k; i < j; ++i) length += segment[i];
    if (length > kWallChordMetricLength * kWallChordStretch) return false;
    if ((before.x != 0.0 || before.y != 0.0) && turn(before, c) > max_turn) return false;
    for (std::size_t i = k + 1; i <= j; ++i) {
      if (turn(c, p[i] - p[i - 1]) > max_turn) return false;
      if (i == j) break;
      // p[i]'s offset from the chord, across it, in the metric at p[i].
      const Vec2 d = p[i] - p[k];
      const double across = cross(c, d) / lc;
      if (m[i].length(Vec2{-c.y / lc, c.x / lc} * across) > kWallChordSagitta) return false;
    }
    return true;
  };
  std::vector<Vec2> kept{p[0]};
  std::size_t k = 0;
  while (k + 1 < n) {
    std::size_t j = k + 1;
    // The longest chord within unit length, or one a little longer where that is nearer to 1.
    double length = segment[k];
    while (j + 1 < n && curve.critical[j] == 0 && fits(k, j + 1) &&
           (length + segment[j] <= kWallChordMetricLength ||
            length + segment[j] - kWallChordMetricLength < kWallChordMetricLength - length)) {
      length += segment[j];
      ++j;
    }
    // An input segment longer than that in the metric is split into equal parts of about unit length.
    const int parts = j == k + 1 ? std::max(1, static_cast<int>(std::lround(segment[k] / kWallChordMetricLength))) : 1;
    for (int q = 1; q < parts; ++q) kept.push_back(p[k] + (p[j] - p[k]) * (static_cast<double>(q) / parts));
    kept.push_back(p[j]);
    before = p[j] - p[k];
    k = j;
  }
  return kept;
}

}  // namespace

// The geometry with each of `walls` reduced to its wall_stations under `metric` (`offset`: the
// layer's thickness; the other curves as they are): what the layers of a table under a metric field grow from.
Geometry metric_wall_geometry(const Geometry& geometry, const std::vector<int>& walls, const GeometryTree& domain,
                              const MetricField& metric, double offset, const GeometryOptions& options) {
  std::vector<RawCurve> raw;
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    RawCurve r{curve.name, {}, curve.file, curve.line, {}, curve.fixed_points};
    r.constraint = curve.constraint;
    if (std::find(walls.begin(), walls.end(), static_cast<int>(c)) != walls.end()) {
      r.points = wall_stations(curve, domain, metric, offset);
    } else {
      r.points = curve.points;
    }
    raw.push_back(std::move(r));
  }
  return build_geometry(std::move(raw), options);
}

double MetricSizeAlongRay::operator()(Vec2 p) const {
  double best = std::numeric_limits<double>::infinity();
  Vec2 foot = p;
  for (const Segment& s : segments_) {
    const Vec2 ab = s.b - s.a;
    const double t = std::clamp(dot(p - s.a, ab) / dot(ab, ab), 0.0, 1.0);
    const Vec2 f = s.a + ab * t;
    if (const double d = dist(p, f); d < best) best = d, foot = f;
  }
  const Metric m = metric_.at(p);
  if (!(best > 0.0)) {  // on the wall: the smaller of the metric's sizes
    return 1.0 / std::sqrt(eigen(m).lambda1);
  }
  const Vec2 u = (p - foot) * (1.0 / best);
  return 1.0 / m.length(u);
}

FrontGradedMetric::FrontGradedMetric(const MetricField& base, std::vector<FrontMetricSource> sources, double gradation)
    : base_(base), sources_(std::move(sources)), gradation_(gradation) {
  std::sort(sources_.begin(), sources_.end(), [](const FrontMetricSource& a, const FrontMetricSource& b) {
    return a.p.x < b.p.x || (a.p.x == b.p.x && a.p.y < b.p.y);
  });
}

namespace {

// m intersected with the metric of size `size` along u (a unit vector) and none across it (the slab
// |u . x| <= size): m + c u uᵀ with c = 1 / size² - 1 / (uᵀ m⁻¹ u), which is what the simultaneous
// reduction of the two gives (docs/metric-fields.md), where m's unit ball reaches farther along u
// than `size`; m itself where it does not (c <= 0), from which it grows continuously as size falls.
Metric within_along(const Metric& m, Vec2 u, double size) {
  const double extent2 = (m.m22 * u.x * u.x - 2.0 * m.m12 * u.x * u.y + m.m11 * u.y * u.y) / m.det();
  const double c = 1.0 / (size * size) - 1.0 / extent2;
  if (!(c > 0.0)) return m;
  return {m.m11 + c * u.x * u.x, m.m12 + c * u.x * u.y, m.m22 + c * u.y * u.y};
}

}  // namespace

Metric FrontGradedMetric::at(Vec2 p) const {
  const Metric m = base_.at(p);
  // sqrt(trace / det) >= 1 / sqrt(lambda2), the base metric's largest size: a source whose size
  // across its front at p is above it asks for nothing there. Sources farther than the best size so
  // far / gradation in x cannot lower it: scan outwards from p.x until then.
  double best = std::sqrt((m.m11 + m.m22) / m.det());
  const FrontMetricSource* source = nullptr;
  const auto consider = [&](const FrontMetricSource& s) {
    if (const double size = s.across + gradation_ * dist(p, s.p); size < best) best = size, source = &s;
  };
  const auto mid = std::lower_bound(sources_.begin(), sources_.end(), p.x,
                                    [](const FrontMetricSource& s, double x) { return s.p.x < x; });
  for (auto it = mid; it != sources_.end() && gradation_ * (it->p.x - p.x) < best; ++it) consider(*it);
  for (auto it = mid; it != sources_.begin();) {
    --it;
    if (gradation_ * (p.x - it->p.x) >= best) break;
    consider(*it);
  }
  if (source == nullptr) return m;
  const Metric across = within_along(m, source->u, best);
  if (!(source->along > 0.0)) return across;
  return within_along(across, Vec2{-source->u.y, source->u.x}, source->along + gradation_ * dist(p, source->p));
}

}  // namespace pdmesh
