// Closest point of a curve within a range of arc positions (see curve_projection.hpp).
#include "geometry/curve_projection.hpp"

#include <algorithm>
#include <cmath>

namespace pdmesh {

namespace {

Vec2 unit(Vec2 v) {
  const double n = norm(v);
  return n > 0.0 ? (1.0 / n) * v : Vec2{};
}

Vec2 segment_tangent(const Curve& curve, int k) {
  const auto i = static_cast<std::size_t>(k);
  return unit(curve.points[i + 1] - curve.points[i]);
}

}  // namespace

CurvePoint closest_on_curve_range(const Curve& curve, Vec2 p, double arc_lo, double arc_hi) {
  const int segments = curve.segment_count();
  CurvePoint best;
  double best2 = HUGE_VAL;
  // First segment that reaches arc_lo.
  int k = static_cast<int>(std::upper_bound(curve.arc.begin(), curve.arc.end(), arc_lo) - curve.arc.begin()) - 1;
  k = std::clamp(k, 0, segments - 1);
  for (; k < segments && curve.arc[static_cast<std::size_t>(k)] <= arc_hi; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double s0 = curve.arc[i], len = curve.arc[i + 1] - s0;
    const double t_lo = std::max(0.0, (arc_lo - s0) / len), t_hi = std::min(1.0, (arc_hi - s0) / len);
    if (t_lo > t_hi) continue;
    const Vec2 a = curve.points[i], b = curve.points[i + 1], d = b - a;
    const double t = std::clamp(dot(p - a, d) / dot(d, d), t_lo, t_hi);
    const Vec2 on = t == 0.0 ? a : t == 1.0 ? b : a + t * d;
    const double dist2 = norm2(p - on);
    if (dist2 < best2) {
      best2 = dist2;
      best.p = on;
      best.arc = t == 1.0 ? curve.arc[i + 1] : s0 + t * len;
      best.distance = std::sqrt(dist2);
      // At a vertex the node slides along the mean direction of both segments.
      Vec2 tangent = segment_tangent(curve, k);
      if (t == 0.0 && k > 0) tangent = unit(tangent + segment_tangent(curve, k - 1));
      if (t == 1.0 && k + 1 < segments) tangent = unit(tangent + segment_tangent(curve, k + 1));
      best.tangent = tangent;
    }
  }
  return best;
}

}  // namespace pdmesh
