// The metric length of a stretch of a curve (curve_metric_length.hpp).
#include "spacing/curve_metric_length.hpp"

#include <algorithm>
#include <cmath>

namespace pdmesh {

double curve_metric_length(const Curve& curve, const MetricField& metric, double arc_a, double arc_b) {
  if (curve.points.size() < 2) return 0.0;
  const double lo = std::clamp(std::min(arc_a, arc_b), 0.0, curve.length());
  const double hi = std::clamp(std::max(arc_a, arc_b), 0.0, curve.length());
  if (!(hi > lo)) return 0.0;
  // The first segment that reaches past lo.
  auto k = static_cast<std::size_t>(std::upper_bound(curve.arc.begin(), curve.arc.end(), lo) - curve.arc.begin());
  k = std::clamp<std::size_t>(k, 1, curve.points.size() - 1) - 1;
  double total = 0.0;
  for (; k + 1 < curve.points.size() && curve.arc[k] < hi; ++k) {
    const double s0 = std::max(lo, curve.arc[k]), s1 = std::min(hi, curve.arc[k + 1]);
    const double seg = curve.arc[k + 1] - curve.arc[k];
    if (!(s1 > s0) || !(seg > 0.0)) continue;
    const Vec2 a = curve.points[k], d = curve.points[k + 1] - a;
    const Vec2 t = (1.0 / seg) * d;  // the unit tangent
    const double step = (s1 - s0) / kCurveMetricSamples;
    for (int j = 0; j < kCurveMetricSamples; ++j) {
      const double s = s0 + (j + 0.5) * step;
      total += step * metric.at(a + ((s - curve.arc[k]) / seg) * d).length(t);
    }
  }
  return total;
}

double curve_metric_half(const Curve& curve, const MetricField& metric, double arc_a, double arc_b) {
  const double total = curve_metric_length(curve, metric, arc_a, arc_b);
  if (!(total > 0.0)) return 0.5 * (arc_a + arc_b);
  double lo = arc_a, hi = arc_b;  // the half lies between lo and hi, measured from arc_a
  const double tolerance = 1e-9 * std::fabs(arc_b - arc_a);
  while (std::fabs(hi - lo) > tolerance) {
    const double mid = 0.5 * (lo + hi);
    if (curve_metric_length(curve, metric, arc_a, mid) < 0.5 * total)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace pdmesh
