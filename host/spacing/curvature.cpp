// segment_radii: discrete curvature at polyline vertices (circumscribed circle of three consecutive
// points), kept where the turning is consistent, averaged onto segments.
#include "spacing/curvature.hpp"

#include <cmath>
#include <limits>

namespace pdmesh {

std::vector<double> segment_radii(const Geometry& geometry) {
  std::vector<double> radius(geometry.segments.size(), std::numeric_limits<double>::infinity());
  for (const Curve& c : geometry.curves) {
    const std::size_t n = c.points.size();
    if (n < 3) continue;
    // Signed curvature at every interior vertex; 0 at ends, critical points and straight vertices.
    std::vector<double> kappa(n, 0.0);
    for (std::size_t k = 1; k + 1 < n; ++k) {
      if (c.critical[k]) continue;
      const Vec2 u = c.points[k] - c.points[k - 1], v = c.points[k + 1] - c.points[k];
      const double turn = std::atan2(cross(u, v), dot(u, v));
      const double chord = dist(c.points[k - 1], c.points[k + 1]);
      if (turn != 0.0 && chord > 0.0) kappa[k] = 2.0 * std::sin(turn) / chord;
    }
    std::vector<double> kept(n, 0.0);
    for (std::size_t k = 1; k + 1 < n; ++k) {
      if (kappa[k] == 0.0) continue;
      const bool before = kappa[k - 1] != 0.0 && (kappa[k - 1] > 0.0) == (kappa[k] > 0.0);
      const bool after = kappa[k + 1] != 0.0 && (kappa[k + 1] > 0.0) == (kappa[k] > 0.0);
      if (before || after) kept[k] = std::fabs(kappa[k]);
    }
    for (int k = 0; k < c.segment_count(); ++k) {
      const double a = kept[static_cast<std::size_t>(k)], b = kept[static_cast<std::size_t>(k) + 1];
      const int count = (a > 0.0 ? 1 : 0) + (b > 0.0 ? 1 : 0);
      if (count == 0) continue;
      radius[static_cast<std::size_t>(c.first_segment + k)] = count / (a + b);
    }
  }
  return radius;
}

}  // namespace pdmesh
