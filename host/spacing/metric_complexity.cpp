// Complexity integrals of metric fields (metric_complexity.hpp).
#include "spacing/metric_complexity.hpp"

#include <algorithm>
#include <cmath>

#include "core/gauss_legendre.hpp"

namespace pdmesh {

double complexity_on_box(const MetricField& field, const Box& box, int panels, int order) {
  const QuadratureRule rule = gauss_legendre01(order);
  panels = std::max(panels, 1);
  const std::size_t n = rule.x.size() * static_cast<std::size_t>(panels);
  std::vector<double> xs(n), ys(n), w(n);
  for (int c = 0; c < panels; ++c)
    for (std::size_t k = 0; k < rule.x.size(); ++k) {
      const std::size_t i = c * rule.x.size() + k;
      const double s = (c + rule.x[k]) / panels;
      xs[i] = box.lo.x + s * box.width();
      ys[i] = box.lo.y + s * box.height();
      w[i] = rule.w[k] / panels;
    }
  double total = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    double row = 0.0;
    for (std::size_t i = 0; i < n; ++i) row += w[i] * std::sqrt(std::max(field.at({xs[i], ys[j]}).det(), 0.0));
    total += w[j] * row;
  }
  return total * box.width() * box.height();
}

double complexity_on_mesh(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                          const std::vector<Metric>& metrics) {
  double total = 0.0;
  for (const auto& t : triangles) {
    const double area = 0.5 * std::fabs(cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]));
    double s = 0.0;
    for (int k = 0; k < 3; ++k) s += std::sqrt(std::max(metrics[t[k]].det(), 0.0));
    total += area * s / 3.0;
  }
  return total;
}

}  // namespace pdmesh
